#!/usr/bin/env bash
# Build geotex with AddressSanitizer + UndefinedBehaviorSanitizer (build-asan/) and run the whole test
# suite under them: every CTest test, then the Python tests (pytest) with the ASan runtime preloaded into
# the interpreter (GEOTEX_SANITIZE_PYTHON=0 skips them).
# Any sanitizer report fails the run. Usage: scripts/sanitize.sh [extra cmake args]
# The build uses Eigen's SimplicialLDLT instead of CHOLMOD (-DGEOTEX_USE_CHOLMOD=OFF), so the fallback
# solver path is tested too. Tests may shrink their problems when GEOTEX_SANITIZE is set (it is here).
set -euo pipefail
cd "$(dirname "$0")/.."
jobs=$(nproc 2>/dev/null || echo 2)
build=build-asan
start=$(date +%s)
source scripts/generator.sh

cmake -S . -B "$build" -G "$(generator "$build")" -DCMAKE_BUILD_TYPE=RelWithDebInfo "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O1 -g1 -DNDEBUG" \
  -DGEOTEX_SANITIZE=ON -DGEOTEX_USE_CHOLMOD=OFF -DGEOTEX_BUILD_BENCH=OFF "$@" >/dev/null
cmake --build "$build" -j"$jobs"
echo "sanitize: built in $(( $(date +%s) - start )) s"

export GEOTEX_SANITIZE=1
# tests/cli_properties.py (CTest cli_properties): a third of its mesh-by-command runs, each command on a third
# of the meshes (368 s under ASan for all of them; scripts/test.sh runs all).
export GEOTEX_PROPERTIES_SHARE=3
# abort_on_error: a report kills the process (no partially passing test). detect_leaks: LeakSanitizer.
export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
status=0
# python_pip_install builds and installs an uninstrumented copy (build-pip/): nothing for the sanitizers to
# check, and scripts/test.sh runs it.
# tests/sanitize-skip.txt: the tests left out here (each with its reason; all of them run in scripts/test.sh).
skip_ctest=$(sed -n 's/^ctest[[:space:]]\+\([^[:space:]#]\+\).*/\1/p' tests/sanitize-skip.txt | sed 's/\./\\./g' | paste -sd'|' -)
skip_pytest=()
while read -r node; do skip_pytest+=(--deselect "$node"); done \
  < <(sed -n 's/^pytest[[:space:]]\+\([^[:space:]#]\+\).*/\1/p' tests/sanitize-skip.txt)
echo "sanitize: $(grep -c '^ctest' tests/sanitize-skip.txt) CTest and $(( ${#skip_pytest[@]} / 2 )) pytest tests left out (tests/sanitize-skip.txt)"
ctest --test-dir "$build" --output-on-failure -j"$jobs" -E "^(python_tests|python_pip_install${skip_ctest:+|$skip_ctest})\$" || status=1

# The Python module is an ASan-instrumented extension of an uninstrumented /usr/bin/python3: the ASan
# runtime must be loaded first (LD_PRELOAD), and with it libstdc++, or ASan's __cxa_throw interceptor
# finds no real __cxa_throw (python3 does not link libstdc++) and the first C++ exception aborts. The
# interpreter's own never-freed allocations are not leaks (detect_leaks=0 here; the C++ tests above
# check for leaks).
if [ "${GEOTEX_SANITIZE_PYTHON:-1}" = 1 ]; then
  if [ -d "$build/python/geotex" ]; then
    libasan=$(${CXX:-c++} -print-file-name=libasan.so)
    libstdcxx=$(${CXX:-c++} -print-file-name=libstdc++.so)
    data=$(sed -n 's/^GEOTEX_DATA_DIR:PATH=//p' "$build/CMakeCache.txt")
    # One OpenMP thread here (scripts/test.sh runs them with every core): a result that depended on the
    # thread count, or a test that passed only with threads, shows as a difference between the two runs.
    echo "sanitize: python tests with LD_PRELOAD=$libasan:$libstdcxx, OMP_NUM_THREADS=1"
    if ! OMP_NUM_THREADS=1 LD_PRELOAD="$libasan:$libstdcxx" ASAN_OPTIONS=detect_leaks=0:abort_on_error=1 \
         PYTHONPATH="$build/python" GEOTEX_CLI="$build/geotex" GEOTEX_DATA="$data" \
         /usr/bin/python3 -m pytest -q -p no:cacheprovider --durations=15 "${skip_pytest[@]}" python/tests; then
      status=1
    fi
  else
    echo "sanitize: the Python module was not built (pybind11 or numpy missing?): python tests not run"
    status=1
  fi
fi
echo "sanitize: $([ $status -eq 0 ] && echo passed || echo FAILED) in $(( $(date +%s) - start )) s"
exit $status
