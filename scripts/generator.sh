# Sourced by the build scripts. generator [BUILD_DIR]: the CMake generator to configure with: the one a
# build tree was configured with already (CMake refuses to switch), else Ninja when installed (it keeps
# both cores busy to the end of a build; scripts/setup.sh installs it), else Unix Makefiles.
generator() {
  local dir=${1:-} g=""
  if [ -n "$dir" ] && [ -f "$dir/CMakeCache.txt" ]; then
    g=$(sed -n 's/^CMAKE_GENERATOR:INTERNAL=//p' "$dir/CMakeCache.txt")
  fi
  if [ -z "$g" ]; then
    if command -v ninja >/dev/null 2>&1; then g=Ninja; else g="Unix Makefiles"; fi
  fi
  echo "$g"
}
