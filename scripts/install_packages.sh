#!/usr/bin/env bash
# Installs the Debian packages named on the command line that are missing (apt-get, as root
# or through sudo). When another apt or dpkg holds the package manager's lock, waits for it
# up to LOCUS_APT_WAIT seconds (default 600) before giving up.
#   scripts/install_packages.sh clang libclang-rt-14-dev
set -euo pipefail

missing=()
for p in "$@"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
((${#missing[@]})) || exit 0

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

echo "setup: installing ${missing[*]}" >&2
wait_for_apt
# The lock can be taken again between the check and apt-get: apt waits for it too.
$SUDO apt-get -o DPkg::Lock::Timeout="$APT_WAIT" update -qq
DEBIAN_FRONTEND=noninteractive $SUDO apt-get -o DPkg::Lock::Timeout="$APT_WAIT" install -y -qq \
  --no-install-recommends "${missing[@]}" >&2

