#!/usr/bin/env bash
# The sanitizer suites, which .ci/run runs after the ci preset's whole suite:
#   ASan + UBSan + LeakSanitizer (preset asan): the unit and integration labels, and the storage
#     receiver's tests;
#   ThreadSanitizer (preset tsan): the unit and integration labels, the storage receiver's tests
#     (its association threads, several senders, stop while peers stall), and the render tests
#     that run threads of their own (below).
# Any sanitizer report ends the test's process with a failing status, so the test fails.
# The receiver's tests include the DICOMweb client's fault tests (its hostile HTTP server), the
# multipart reader, and a study of three series retrieved over three associations at once from
# one Orthanc (the retrieve's worker and builder threads).
# Of the render label, TSan runs the tests whose C++ runs threads of its own beside the GL
# context: the working set's loader feeding the ray caster, the CPU reference's parallel rows in
# every mode, interactive frames, a batch of light-field views and the CLI's GL render. The other
# render tests compare one more shader feature with the CPU reference through the same threaded
# code; TSan sees neither GLSL nor Mesa, and they took 13 of TSan's 25 minutes (they run in the
# ci preset).
# Left to the ci preset, with the reason: the fuzz label (its own clang ASan/UBSan build and
# corpus), the .deb package test (it packages the ci tree), the gui label and the Orthanc PACS
# tests (minutes of peer set-up each; the receiver's own tests above cover Holovox's threads).
#
#   bash tests/sanitizers/run.sh [asan|tsan]    both when no argument
set -euo pipefail
cd "$(dirname "$0")/../.."
here="$PWD/tests/sanitizers"
export ASAN_OPTIONS="detect_leaks=1:halt_on_error=1:abort_on_error=0:detect_stack_use_after_return=1:check_initialization_order=1:strict_init_order=1"
export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1"
export LSAN_OPTIONS="suppressions=$here/lsan.supp:print_suppressions=0"
export TSAN_OPTIONS="halt_on_error=1:second_deadlock_stack=1:suppressions=$here/tsan.supp:print_suppressions=0"
targets="core_unit_tests dicom_unit_tests ui_unit_tests cli_tests pacs_tests holovox-cli holovox-lightfield-mpi"
receiver='^(StorageServer|StorageLimits|DicomWebFaults)\.|^DicomWebPeer\.Parallel|^MultipartReader\.'
threadedRender='^(ShaderLibrary|ShaderTraversal|GpuRayCaster|InteractiveFrames|EglOffscreenContext)\.|^LightField\.ABatch|^CliGlCommands\.RenderDrawsATimePoint'

# Each step's status is checked by hand: `set -e` does not apply inside a function called from
# an && list, which is how a failing sanitizer stage once printed "passed".
suite() {  # preset labels what (in words) [render tests (a name regex)]
    local preset=$1 labels=$2 what=$3 render=${4:-} start=$SECONDS failed=0
    cmake --preset "$preset" >/dev/null || return 1
    # shellcheck disable=SC2086
    cmake --build --preset "$preset" --target $targets ${render:+render_context_tests} || return 1
    ctest --test-dir "build/$preset" -L "$labels" -LE fuzz -E package_deb -j2 --timeout 900 --output-on-failure || failed=1
    ctest --test-dir "build/$preset" -R "$receiver" --timeout 900 --output-on-failure || failed=1  # one at a time
    if [ -n "$render" ]; then
        ctest --test-dir "build/$preset" -L render -R "$render" -j2 --timeout 900 --output-on-failure || failed=1
    fi
    if [ "$failed" != 0 ]; then
        echo "sanitizers: $preset ($labels, $what) FAILED after $((SECONDS - start)) s"
        return 1
    fi
    echo "sanitizers: $preset ($labels, $what) passed in $((SECONDS - start)) s"
}
asan() { suite asan 'unit|integration' 'the receiver'; }
tsan() { suite tsan 'unit|integration' 'the receiver, the threaded render tests' "$threadedRender"; }

status=0
case "${1:-both}" in
    asan) asan || status=1 ;;
    tsan) tsan || status=1 ;;
    both) asan || status=1
          tsan || status=1 ;;
    *) echo "usage: $0 [asan|tsan]" >&2; exit 2 ;;
esac
exit "$status"
