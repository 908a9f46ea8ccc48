#!/usr/bin/env bash
# Builds the fuzzers with the `fuzz` preset (clang, libFuzzer, ASan + UBSan) and runs them:
#  - dicom_fuzzer, seeded with pydicom's real-world test files (big endian, implicit VR, deflate,
#    RLE, JPEG, JPEG-LS, JPEG 2000, truncated files, DICOMDIRs) and tests/fuzz/regressions/;
#  - hvo_fuzzer, seeded with small .hvo files of every type and codec (hvo_seeds), its inputs'
#    checksums made valid so that it explores forged files, not checksum failures;
#  - volume_fuzzer, seeded with tests/fuzz/volume_seeds/ (MetaImage plain, big-endian and
#    zlib-compressed, NRRD raw, gzip, with skips and 4-D, NIfTI plain, gzip and float64, legacy VTK short and
#    double, MetaImage and legacy VTK in ASCII; the first byte of each
#    picks the format).
# Every seed is executed under the sanitizers first, then mutated.
# -malloc_limit_mb is above 4 GiB because DCMTK must read deflated streams eagerly and asks
# (nothrow) for an element's declared length, up to 4 GiB, before finding the data short;
# the resident memory limit (-rss_limit_mb) still catches any real blow-up.
#
#   bash tests/fuzz/run_fuzz.sh [SECONDS]     explore each fuzzer for SECONDS (default 30)
#   bash tests/fuzz/run_fuzz.sh --ci          the test suite's run: fixed seed and 6000 inputs
#                                             for DICOM, 3000 for .hvo and for volume files,
#                                             so CI is reproducible
#                                             (new findings come from exploration runs and land
#                                             in regressions/)
# A missing corpus is a failure, not a pass. Crashing inputs are kept in build/fuzz/artifacts/.
set -euo pipefail
cd "$(dirname "$0")/../.."
seconds=${1:-30}
dicomLimits="-max_total_time=$seconds"
hvoLimits="-max_total_time=$seconds"
volumeLimits="-max_total_time=$seconds"
if [ "$seconds" = "--ci" ]; then dicomLimits="-seed=1 -runs=6000"; hvoLimits="-seed=1 -runs=3000"; volumeLimits="-seed=1 -runs=3000"; fi
cmake --preset fuzz >/dev/null
cmake --build --preset fuzz --target dicom_fuzzer hvo_fuzzer hvo_seeds volume_fuzzer >/dev/null
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
export HVX_FUZZ_SCRATCH="$work"
artifacts=build/fuzz/artifacts
mkdir -p "$work/dicom" "$work/hvo" "$work/volume" "$artifacts"
corpus=/usr/lib/python3/dist-packages/pydicom/data/test_files
[ -d "$corpus" ] || { echo "no seed corpus: $corpus is missing (python3-pydicom)"; exit 1; }
find "$corpus" -type f -size -2M -exec cp {} "$work/dicom/" \;
cp tests/fuzz/regressions/* "$work/dicom/"  # inputs that once crashed
build/fuzz/tests/fuzz/hvo_seeds "$work/hvo" >/dev/null
cp tests/fuzz/volume_seeds/* "$work/volume/"
for seeds in dicom hvo volume; do
  n=$(ls "$work/$seeds" | wc -l)
  [ "$n" -ge 9 ] || { echo "$seeds seed corpus has only $n files"; exit 1; }
done

fail=0
run() { # name binary limits corpus
  local name=$1 bin=$2 limits=$3 dir=$4
  echo "$name: fuzzing with $(ls "$dir" | wc -l) seed files ($limits)"
  set +e
  ASAN_OPTIONS=detect_leaks=0:allocator_may_return_null=1 UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1 \
    "$bin" $limits -rss_limit_mb=2560 -malloc_limit_mb=4200 -max_len=262144 \
    -timeout=20 -print_final_stats=1 -artifact_prefix="$work/$name-" "$dir" >"$work/$name.log" 2>&1
  local rc=$?
  set -e
  grep -E "^(INFO: seed corpus|#[0-9]+ +DONE|stat::number_of_executed_units|stat::peak_rss_mb)" "$work/$name.log" || true
  # libFuzzer exits non-zero and writes an artefact on any crash, leak, timeout or sanitizer report.
  if [ $rc -ne 0 ] || ls "$work/$name-"crash-* "$work/$name-"timeout-* "$work/$name-"oom-* >/dev/null 2>&1; then
    grep -E "ERROR|SUMMARY|runtime error|==[0-9]+==" "$work/$name.log" | head -20
    cp "$work/$name-"crash-* "$work/$name-"timeout-* "$work/$name-"oom-* "$artifacts/" 2>/dev/null || true
    echo "$name: fuzzer found a failure (exit $rc); inputs saved in $artifacts/"
    fail=1
  fi
}
run dicom build/fuzz/tests/fuzz/dicom_fuzzer "$dicomLimits" "$work/dicom"
run hvo build/fuzz/tests/fuzz/hvo_fuzzer "$hvoLimits" "$work/hvo"
run volume build/fuzz/tests/fuzz/volume_fuzzer "$volumeLimits" "$work/volume"
[ $fail -eq 0 ] && echo "no crash, no sanitizer report"
exit $fail
