#!/usr/bin/env bash
# Whitted: the two commands of the README, plus their building blocks.
#
#   ./whitted.sh render [--out whitted.png] [--size 800x600] ...   main job: render the default scene, print report
#   ./whitted.sh test                                              install, build every configuration, run all tests
#   ./whitted.sh package                                           Debian packages into build/packages (README)
#
# Each installs what it needs (Debian 12 packages, as root: render only VTK, GLM and the build tools) and is
# idempotent: a second run only rebuilds what changed. Build trees live under $WHITTED_BUILD_DIR (default ./build):
#   build/vtk       core + VTK module (system VTK 9.1) + tests          (the main configuration)
#   build/paraview  the same plugin/ sources against ParaView 5.11's VTK (ParaView plugin)
#   build/asan      core + VTK module + C++ tests with AddressSanitizer + UndefinedBehaviorSanitizer (clang)
#   build/tsan      core tests with ThreadSanitizer (clang)
#   build/fuzz      libFuzzer targets (clang)
#   build/pvprefix  python3-paraview unpacked privately (it conflicts with python3-vtk9; see README)
set -euo pipefail

ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
BUILD="${WHITTED_BUILD_DIR:-$ROOT/build}"
JOBS="$(nproc)"
XVFB=(xvfb-run -a -s "-screen 0 1280x1024x24 -noreset")
# For a second X server started at the same moment (the sanitizer suites beside the main one): free numbers from
# 150 up, so the two never race for one number. A precaution: with several xvfb-run started together on this
# machine (test loops beside a suite), 5 tests of a suite once failed with "bad X server connection" mid-run; the
# mechanism was not pinned down, and CI had never shown it.
XVFB2=(xvfb-run -n 150 -a -s "-screen 0 1280x1024x24 -noreset")

# Debian 12 packages: the main job (render) needs VTK, the build tools and GLM; the tests need the rest
PACKAGES_RENDER=(
  build-essential cmake ninja-build
  libglm-dev libvtk9-dev python3-vtk9
  xvfb xauth
)
PACKAGES_TEST=(
  git pkg-config file
  libgtest-dev libbenchmark-dev python3-numpy python3-matplotlib
  paraview paraview-dev openmpi-bin
  x11-apps imagemagick
  clang libclang-rt-14-dev llvm
  libembree-dev libtbb-dev povray
)

log() { printf '\n== %s\n' "$*" >&2; }

install_packages() {  # render | test (test: everything)
  local wanted=("${PACKAGES_RENDER[@]}")
  [ "$1" = render ] || wanted+=("${PACKAGES_TEST[@]}")
  local missing=()
  for p in "${wanted[@]}"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
  done
  if ((${#missing[@]})); then
    log "installing Debian packages: ${missing[*]}"
    local sudo=""
    [ "$(id -u)" -eq 0 ] || sudo="sudo"
    $sudo apt-get update -qq
    DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
  fi
  [ "$1" = render ] && return
  # python3-paraview conflicts with python3-vtk9 (both ship vtkmodules): unpack it privately instead of installing
  if [ ! -d "$BUILD/pvprefix/usr/lib/python3/dist-packages/paraview" ]; then
    log "unpacking python3-paraview into $BUILD/pvprefix"
    mkdir -p "$BUILD/deb" "$BUILD/pvprefix"
    (cd "$BUILD/deb" && rm -f python3-paraview_*.deb && apt-get download python3-paraview >/dev/null)
    dpkg -x "$BUILD"/deb/python3-paraview_*.deb "$BUILD/pvprefix"
  fi
}

configure_build() {  # name, extra cmake args... (configures again when the arguments change)
  local name="$1"
  shift
  local dir="$BUILD/$name"
  mkdir -p "$BUILD"
  if ! configured_with "$name" "$@"; then
    log "configuring $name"
    cmake -S "$ROOT" -B "$dir" -G Ninja -DPython3_EXECUTABLE=/usr/bin/python3 "$@" >"$BUILD/$name.configure.log" ||
      { cat "$BUILD/$name.configure.log"; return 1; }
    printf '%s' "$*" >"$dir/whitted-configure-args"
  fi
  log "building $name"
  ninja -C "$dir" -j "$JOBS" >"$BUILD/$name.build.log" 2>&1 || { tail -50 "$BUILD/$name.build.log"; return 1; }
}

configured_with() {  # name, cmake args...: the tree was configured with exactly these arguments
  [ -f "$BUILD/$1/build.ninja" ] && [ "$(cat "$BUILD/$1/whitted-configure-args" 2>/dev/null)" = "${*:2}" ]
}

# The main configuration: the VTK module, its Python package and (for the tests) every test and the benchmark.
MAIN_ARGS=(-DCMAKE_BUILD_TYPE=Release -DWHITTED_BUILD_TESTING=ON -DWHITTED_BENCHMARK=ON)
build_main() { configure_build vtk "${MAIN_ARGS[@]}"; }
# The main job's: without tests and benchmark, which need packages it does not install (a tree the tests
# configured already has everything it needs and is kept as it is)
build_render() {
  if configured_with vtk "${MAIN_ARGS[@]}"; then
    build_main
  else
    configure_build vtk -DCMAKE_BUILD_TYPE=Release -DWHITTED_BUILD_TESTING=OFF -DWHITTED_BENCHMARK=OFF
  fi
}

build_paraview() {
  configure_build paraview -DCMAKE_BUILD_TYPE=Release -DWHITTED_PARAVIEW=ON \
    -DPARAVIEW_DEBIAN_PYTHON_PREFIX="$BUILD/pvprefix"
}

build_asan() {
  CC=clang CXX=clang++ configure_build asan -DCMAKE_BUILD_TYPE=RelWithDebInfo -DWHITTED_BENCHMARK=OFF \
    -DCMAKE_CXX_FLAGS="-fsanitize=address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer" \
    -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=address,undefined" -DCMAKE_SHARED_LINKER_FLAGS="-fsanitize=address,undefined"
}

build_tsan() {
  CC=clang CXX=clang++ configure_build tsan -DCMAKE_BUILD_TYPE=RelWithDebInfo -DWHITTED_VTK=OFF \
    -DWHITTED_BENCHMARK=OFF -DCMAKE_CXX_FLAGS="-fsanitize=thread -fno-omit-frame-pointer" \
    -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=thread"
}

build_fuzz() {
  CC=clang CXX=clang++ configure_build fuzz -DCMAKE_BUILD_TYPE=RelWithDebInfo -DWHITTED_FUZZ=ON \
    -DWHITTED_BENCHMARK=OFF -DWHITTED_BUILD_TESTING=ON
}

pv_env() {
  export PYTHONPATH="$BUILD/pvprefix/usr/lib/python3/dist-packages${PYTHONPATH:+:$PYTHONPATH}"
}

cmd_render() {
  install_packages render
  build_render
  log "rendering the default scene through vtkWhittedPass"
  PYTHONPATH="$BUILD/vtk/lib/python3/dist-packages${PYTHONPATH:+:$PYTHONPATH}" \
    "${XVFB[@]}" /usr/bin/python3 "$ROOT/plugin/python/whitted_demo.py" "$@"
}

cmd_test() {
  install_packages test
  build_main
  build_paraview
  build_asan
  build_tsan
  build_fuzz
  local status=0
  local suites=(vtk asan asan-python tsan fuzz paraview)  # one log each: $BUILD/test-<suite>.log
  # Rendering suites under Xvfb, sanitizer suites beside them (2 cores: run the two heavy groups in parallel)
  log "running tests"
  (cd "$BUILD/vtk" && "${XVFB[@]}" ctest -j "$JOBS" --output-on-failure --timeout 900) >"$BUILD/test-vtk.log" 2>&1 &
  local pid_main=$!
  # ASan suite: the C++ tests directly; the Python tests with the ASan runtime preloaded into /usr/bin/python3
  # (an instrumented module needs it loaded first). Not under ASan: the 10M-triangle test (memory), the memory
  # soak (its quarantine keeps freed memory resident) and the benchmark (not built); the ParaView suite builds
  # against ParaView's VTK in its own tree.
  local asan_rt
  asan_rt="$(clang -print-file-name="libclang_rt.asan-$(uname -m).so")"
  (
    cd "$BUILD/asan" || exit 1
    export ASAN_OPTIONS=detect_leaks=0 UBSAN_OPTIONS=print_stacktrace=1
    s=0
    "${XVFB2[@]}" ctest --output-on-failure --timeout 900 -LE "python|benchmark|paraview|large|install|soak" \
      >"$BUILD/test-asan.log" 2>&1 || s=1
    "${XVFB2[@]}" env LD_PRELOAD="$asan_rt" ctest --output-on-failure --timeout 900 -L python \
      >"$BUILD/test-asan-python.log" 2>&1 || s=1
    exit $s
  ) &
  local pid_asan=$!
  wait $pid_main || status=1
  wait $pid_asan || status=1
  # ThreadSanitizer on the multithreaded tests: thread pool, renderer, parallel build, background upgrade, a large
  # volume's passes over its scalars (the rest is single-threaded)
  (cd "$BUILD/tsan" && TSAN_OPTIONS="halt_on_error=1" ctest -j "$JOBS" --output-on-failure --timeout 900 \
    -R "ThreadPool\.|Renderer\.|Bvh\.Parallel|Bvh\.Cancel|Scene\.BackgroundUpgrade|VolumeSkip\.LargeGrid|Stability\.(ScaleAndOffset|Grazing|OpticsAtTheEdge)") \
    >"$BUILD/test-tsan.log" 2>&1 || status=1
  (cd "$BUILD/fuzz" && ctest --output-on-failure --timeout 900 -L fuzz) >"$BUILD/test-fuzz.log" 2>&1 || status=1
  pv_env
  (cd "$BUILD/paraview" && "${XVFB[@]}" ctest --output-on-failure --timeout 900) >"$BUILD/test-paraview.log" 2>&1 ||
    status=1
  for suite in "${suites[@]}"; do
    [ -f "$BUILD/test-$suite.log" ] || { status=1; log "suite $suite: no log"; continue; }
    log "suite $suite"
    grep -E "tests passed|tests failed|\*\*\*Failed|Failed  |Timeout|Not Run|\*\*\*Exception" "$BUILD/test-$suite.log" || true
  done
  # One closing line over all suites
  local passed=0 failed=0 line
  for suite in "${suites[@]}"; do
    [ -f "$BUILD/test-$suite.log" ] || continue  # said above
    line=$(grep -E "tests passed, [0-9]+ tests? failed out of [0-9]+" "$BUILD/test-$suite.log" | tail -1) || true
    [ -n "$line" ] || { status=1; log "suite $suite ran no tests"; continue; }
    local f t
    f=$(sed -E 's/.*passed, ([0-9]+) tests? failed out of ([0-9]+).*/\1/' <<<"$line")
    t=$(sed -E 's/.*passed, ([0-9]+) tests? failed out of ([0-9]+).*/\2/' <<<"$line")
    failed=$((failed + f))
    passed=$((passed + t - f))
  done
  ((failed == 0)) || status=1
  if [ "$status" -ne 0 ]; then
    log "FAILURES: full logs in $BUILD/test-*.log"
    for suite in "${suites[@]}"; do
      [ -f "$BUILD/test-$suite.log" ] && grep -q "tests failed" "$BUILD/test-$suite.log" && tail -80 "$BUILD/test-$suite.log"
    done
  fi
  echo "tests: $passed passed, $failed failed"
  return $status
}

cmd_package() {  # the Debian packages whitted-vtk and whitted-paraview, into $BUILD/packages
  install_packages test
  build_main
  build_paraview
  rm -rf "$BUILD/packages"
  for name in vtk paraview; do
    log "packaging $name"
    (cd "$BUILD/$name" && cpack -G DEB -B "$BUILD/packages" >"$BUILD/package-$name.log" 2>&1) ||
      { cat "$BUILD/package-$name.log"; return 1; }
  done
  rm -rf "$BUILD/packages/_CPack_Packages"
  for deb in "$BUILD"/packages/*.deb; do
    printf '%s  %s KiB\n  Depends: %s\n' "$deb" "$(($(stat -c %s "$deb") / 1024))" "$(dpkg-deb -f "$deb" Depends)"
  done
  echo "install with: apt install $BUILD/packages/whitted-vtk_*.deb $BUILD/packages/whitted-paraview_*.deb"
}

case "${1:-}" in
  render) shift; cmd_render "$@" ;;
  test) shift; cmd_test "$@" ;;
  package) shift; cmd_package "$@" ;;
  install) install_packages test ;;
  *) echo "usage: $0 render [options] | test | package" >&2; exit 2 ;;
esac
