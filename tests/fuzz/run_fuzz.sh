#!/usr/bin/env bash
# Builds the DICOM fuzzer with the `fuzz` preset (clang, libFuzzer, ASan + UBSan) and runs it,
# seeded with pydicom's real-world test files (big endian, implicit VR, deflate, RLE, JPEG,
# JPEG-LS, JPEG 2000, truncated files, DICOMDIRs) and a few series Holovox writes itself.
# Every seed is executed under the sanitizers first, then mutated for SECONDS seconds.
# -malloc_limit_mb is above 4 GiB because DCMTK must read deflated streams eagerly and asks
# (nothrow) for an element's declared length, up to 4 GiB, before finding the data short;
# the resident memory limit (-rss_limit_mb) still catches any real blow-up.
#
#   bash tests/fuzz/run_fuzz.sh [SECONDS]     explore for SECONDS (default 30)
#   bash tests/fuzz/run_fuzz.sh --ci          the test suite's run: fixed seed and 6000 inputs,
#                                             so CI is reproducible (new findings come from
#                                             exploration runs and land in regressions/)
set -euo pipefail
cd "$(dirname "$0")/../.."
seconds=${1:-30}
limits="-max_total_time=$seconds"
if [ "$seconds" = "--ci" ]; then seconds="fixed"; limits="-seed=1 -runs=6000"; fi
cmake --preset fuzz >/dev/null
cmake --build --preset fuzz --target dicom_fuzzer >/dev/null
work=$(mktemp -d)
trap 'rm -rf "$work" /tmp/hvx-fuzz-*.dcm' EXIT
mkdir -p "$work/corpus"
find /usr/lib/python3/dist-packages/pydicom/data/test_files -type f -size -2M -exec cp {} "$work/corpus/" \; 2>/dev/null || true
cp tests/fuzz/regressions/* "$work/corpus/" 2>/dev/null || true  # inputs that once crashed
n=$(ls "$work/corpus" | wc -l)
echo "fuzzing with $n seed files ($limits)"
set +e
ASAN_OPTIONS=detect_leaks=0:allocator_may_return_null=1 UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1 \
  build/fuzz/tests/fuzz/dicom_fuzzer $limits -rss_limit_mb=2560 -malloc_limit_mb=4200 -max_len=262144 \
  -timeout=20 -print_final_stats=1 -artifact_prefix="$work/" "$work/corpus" >"$work/log" 2>&1
rc=$?
set -e
grep -E "^(INFO: seed corpus|#[0-9]+ +DONE|stat::number_of_executed_units|stat::peak_rss_mb)" "$work/log" || true
# libFuzzer exits non-zero and writes an artefact on any crash, leak, timeout or sanitizer report.
if [ $rc -ne 0 ] || ls "$work"/crash-* "$work"/timeout-* "$work"/oom-* >/dev/null 2>&1; then
  grep -E "ERROR|SUMMARY|runtime error|==[0-9]+==" "$work/log" | head -20
  mkdir -p fuzz-artifacts && cp "$work"/crash-* "$work"/timeout-* "$work"/oom-* fuzz-artifacts/ 2>/dev/null || true
  echo "fuzzer found a failure (exit $rc); inputs saved in fuzz-artifacts/"
  exit 1
fi
echo "no crash, no sanitizer report"
