# The instrumented build that scripts/fuzz.sh and scripts/sanitize.sh share
# (source scripts/lib/asan_build.sh from the repository root): clang,
# AddressSanitizer + UBSan, the fuzz targets on, in build-asan/.
build=build-asan

# Configures $build, its log in $build.log; exits 1 showing the log on
# failure.
configure_asan_build() {
  local launcher=()
  command -v ccache > /dev/null &&
    launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
  CXX=clang++ cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    -DES_FUZZ=ON -DES_SANITIZE=address,undefined "${launcher[@]}" \
    > "$build.log" 2>&1 || { cat "$build.log"; exit 1; }
}
