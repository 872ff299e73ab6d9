#!/usr/bin/env bash
# Installs the Debian packages Locus needs (only those missing) and builds into build/.
#
#   scripts/setup.sh                      # every target: server, CLI, tests, benchmarks
#   scripts/setup.sh locus-server locus   # only these targets (what run.sh needs)
#
# The targets can also come from LOCUS_TARGETS (space-separated); arguments win.
# LOCUS_DEVTOOLS=1 also installs what the test command's API checks need: Node.js and npm
# (Debian's) and the pinned developer tools of package-lock.json (npm ci, into node_modules/),
# and Chromium, its driver and Selenium for the web viewer's browser test.
# Packages: scripts/install_packages.sh (it waits for a busy package manager).
set -euo pipefail
cd "$(dirname "$0")/.."

targets=("$@")
if ((${#targets[@]} == 0)) && [ -n "${LOCUS_TARGETS:-}" ]; then
  read -r -a targets <<<"$LOCUS_TARGETS"
fi

packages=(g++ cmake make pkg-config libeigen3-dev libcpp-httplib-dev nlohmann-json3-dev libsqlite3-dev
          libgtest-dev libgmock-dev libbenchmark-dev libcli11-dev libutf8proc-dev libopencv-imgproc-dev libpng-dev
          libjpeg-dev libssl-dev zlib1g-dev libjs-leaflet libpq-dev postgresql)
# Build speed only, taken when present (CMakeLists.txt, scripts/configure.sh): a compiler cache, a
# fast linker, a build tool that keeps both cores busy. The Docker image's one-off build does
# without them.
packages+=(ccache mold ninja-build)
# The docs' shell blocks (scripts/docs_blocks.py, a test): Python, and the curl they use.
[ "${LOCUS_DEVTOOLS:-0}" = 1 ] && packages+=(python3 curl)
[ "${LOCUS_DEVTOOLS:-0}" = 1 ] && ! command -v npm >/dev/null 2>&1 && packages+=(nodejs npm)
# The web viewer's browser test (tests/browser/): a real headless Chromium driven by Selenium.
[ "${LOCUS_DEVTOOLS:-0}" = 1 ] && packages+=(chromium chromium-driver python3-selenium)
# scripts/check_deploy_config.sh: nginx -t on docker/nginx.conf, and compose.yaml read as YAML.
[ "${LOCUS_DEVTOOLS:-0}" = 1 ] && packages+=(nginx-light python3-yaml)
source scripts/phase.sh
phase "install packages" bash scripts/install_packages.sh "${packages[@]}"

# A copy of the lock file npm ci last installed from: equal means nothing to do.
if [ "${LOCUS_DEVTOOLS:-0}" = 1 ] && ! cmp -s package-lock.json node_modules/.locus-installed-lock.json 2>/dev/null; then
  echo "setup: installing the pinned developer tools (npm ci)" >&2
  phase "npm ci" npm ci --no-audit --no-fund --loglevel=error >&2
  cp package-lock.json node_modules/.locus-installed-lock.json
fi

BUILD_DIR="${LOCUS_BUILD_DIR:-build}"
JOBS="${LOCUS_JOBS:-2}"
phase "configure ($BUILD_DIR)" bash scripts/configure.sh "$BUILD_DIR" -DCMAKE_BUILD_TYPE=Release >/dev/null
if ((${#targets[@]})); then
  phase "build ${targets[*]}" cmake --build "$BUILD_DIR" -j"$JOBS" --target "${targets[@]}"
else
  phase "build everything ($BUILD_DIR)" cmake --build "$BUILD_DIR" -j"$JOBS"
fi
