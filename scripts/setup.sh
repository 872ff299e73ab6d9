#!/usr/bin/env bash
# Installs the Debian packages Locus needs (only those missing) and builds into build/.
#
#   scripts/setup.sh                      # every target: server, CLI, tests, benchmarks
#   scripts/setup.sh locus-server locus   # only these targets (what run.sh needs)
#
# The targets can also come from LOCUS_TARGETS (space-separated); arguments win.
# LOCUS_DEVTOOLS=1 also installs what the test command's API checks need: Node.js and npm
# (Debian's) and the pinned developer tools of package-lock.json (npm ci, into node_modules/).
# When another apt or dpkg holds the package manager's lock, waits for it up to
# LOCUS_APT_WAIT seconds (default 600) before giving up.
set -euo pipefail
cd "$(dirname "$0")/.."

targets=("$@")
if ((${#targets[@]} == 0)) && [ -n "${LOCUS_TARGETS:-}" ]; then
  read -r -a targets <<<"$LOCUS_TARGETS"
fi

packages=(g++ cmake make pkg-config libeigen3-dev libcpp-httplib-dev nlohmann-json3-dev libsqlite3-dev
          libgtest-dev libgmock-dev libbenchmark-dev libcli11-dev)
[ "${LOCUS_DEVTOOLS:-0}" = 1 ] && ! command -v npm >/dev/null 2>&1 && packages+=(nodejs npm)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done

SUDO=""
[ "$(id -u)" -eq 0 ] || SUDO="sudo"
APT_WAIT="${LOCUS_APT_WAIT:-600}"

# True while some process holds dpkg's or apt's lock files (an unattended upgrade, another
# apt-get). fuser sees them; without it, look for the package managers by name.
apt_busy() {
  if command -v fuser >/dev/null 2>&1; then
    $SUDO fuser /var/lib/dpkg/lock-frontend /var/lib/dpkg/lock /var/lib/apt/lists/lock >/dev/null 2>&1
  else
    pgrep -x 'apt|apt-get|aptitude|dpkg|unattended-upgr' >/dev/null 2>&1
  fi
}

wait_for_apt() {
  local waited=0
  while apt_busy; do
    if ((waited == 0)); then
      echo "setup: another package manager is running (dpkg/apt lock held); waiting up to ${APT_WAIT} s for it to finish..." >&2
    fi
    if ((waited >= APT_WAIT)); then
      echo "setup: the package manager is still busy after ${APT_WAIT} s; try again when it is done" >&2
      exit 1
    fi
    sleep 5
    waited=$((waited + 5))
  done
  ((waited == 0)) || echo "setup: the package manager is free after ${waited} s" >&2
}

if ((${#missing[@]})); then
  echo "setup: installing ${missing[*]}" >&2
  wait_for_apt
  # The lock can be taken again between the check and apt-get: apt waits for it too.
  $SUDO apt-get -o DPkg::Lock::Timeout="$APT_WAIT" update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get -o DPkg::Lock::Timeout="$APT_WAIT" install -y -qq \
    --no-install-recommends "${missing[@]}" >&2
fi

# A copy of the lock file npm ci last installed from: equal means nothing to do.
if [ "${LOCUS_DEVTOOLS:-0}" = 1 ] && ! cmp -s package-lock.json node_modules/.locus-installed-lock.json 2>/dev/null; then
  echo "setup: installing the pinned developer tools (npm ci)" >&2
  npm ci --no-audit --no-fund --loglevel=error >&2
  cp package-lock.json node_modules/.locus-installed-lock.json
fi

BUILD_DIR="${LOCUS_BUILD_DIR:-build}"
JOBS="${LOCUS_JOBS:-2}"
cmake -S . -B "$BUILD_DIR" -DCMAKE_BUILD_TYPE=Release >/dev/null
if ((${#targets[@]})); then
  cmake --build "$BUILD_DIR" -j"$JOBS" --target "${targets[@]}"
else
  cmake --build "$BUILD_DIR" -j"$JOBS"
fi
