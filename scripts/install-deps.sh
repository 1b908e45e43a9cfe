#!/usr/bin/env bash
# Installs the Debian 12 packages clothsim needs to build, test and run.
# Idempotent; run as root (or with sudo) on a fresh machine. Nothing is downloaded at build time.
set -euo pipefail

packages=(
  build-essential cmake ninja-build pkg-config
  ccache               # repeated builds (CMakeLists.txt, .ci/run): the cache lives outside the clone
  nlohmann-json3-dev   # scene files and summary.json
  libtinygltf-dev      # --export gltf (final.glb): its header, compiled into src/io/gltf.cpp
  libcli11-dev         # command-line parsing
  libgtest-dev libgmock-dev  # tests
  libbenchmark-dev     # micro-benchmarks
  python3 python3-numpy  # end-to-end check that numpy.load opens our .npy output
  # The Python module clothsim (python/, docs/python.md): pybind11 and the headers of the system
  # Python it is built for, and pytest for its tests (tests/python).
  pybind11-dev python3-dev python3-pytest
  python3-distributed  # clothsim.sweep(client=...) on a Dask cluster; its tests run a LocalCluster
  # Rendering (src/render, docs/rendering.md): OpenGL 3.3 core through libepoxy, headless EGL
  # on Mesa (llvmpipe where there is no GPU), PNG images, H.264 video through the ffmpeg program.
  libepoxy-dev libegl-dev libgl-dev libegl-mesa0 libgl1-mesa-dri
  libpng-dev
  ffmpeg               # animation.mp4; ffprobe checks it in the tests
  mesa-utils           # eglinfo/glxinfo, to diagnose a machine's OpenGL
  # The interactive viewer (clothsim view, docs/viewer.md): a GLFW window with Dear ImGui; its
  # tests run under a virtual X server.
  libglfw3-dev libimgui-dev xvfb xauth
  # The Vulkan compute module (src/gpu, docs/gpu.md): the loader and headers, glslc to compile
  # the shaders at build time, the validation layers the tests enable, and Mesa's Vulkan drivers,
  # whose lavapipe runs the shaders on the CPU: CI has no GPU, and lavapipe is what the tests
  # use. vulkan-tools has vulkaninfo, to diagnose a machine's Vulkan.
  libvulkan-dev glslc vulkan-validationlayers mesa-vulkan-drivers vulkan-tools
  # Fuzzing (the fuzz preset, tests/fuzz, docs/testing.md): clang with libFuzzer and the clang
  # sanitizer runtimes (libclang-rt-14-dev, only recommended by clang-14, so named here), LLVM's
  # OpenMP for clang builds, and llvm-symbolizer (llvm-14) for readable stacks of findings.
  clang-14 libclang-rt-14-dev libomp-14-dev llvm-14
  # Static analysis (.clang-tidy, scripts/run-clang-tidy.sh, a phase of .ci/run).
  clang-tidy
  # The run report (docs/report.md): its tests open the page in headless Chromium (tests/report).
  chromium
)
# npm, for the three.js the run report embeds (web/package.json): Debian's, where the machine has
# no npm of its own (a Node.js from elsewhere brings its npm, and Debian's would conflict with it).
if ! command -v npm >/dev/null 2>&1; then packages+=(npm); fi

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done

if ((${#missing[@]})); then
  sudo=""
  if [ "$(id -u)" -ne 0 ]; then sudo="sudo"; fi
  echo "install-deps: installing ${missing[*]}"
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
else
  echo "install-deps: all packages present"
fi

# three.js for the run report, from the npm registry at the version web/package-lock.json pins,
# into web/node_modules (the build embeds it: src/CMakeLists.txt). Again only when the lock changed.
web="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)/web"
if [ ! -f "$web/node_modules/.package-lock.json" ] || [ "$web/package-lock.json" -nt "$web/node_modules/.package-lock.json" ]; then
  echo "install-deps: npm ci in web/ (three.js for the run report)"
  npm ci --prefix "$web" --no-audit --no-fund --loglevel=error
else
  echo "install-deps: web/node_modules is up to date"
fi
