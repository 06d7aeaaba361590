#!/usr/bin/env bash
# Installs the Debian packages listed in deploy/packages.txt (or the list given) that are not installed yet.
# Idempotent: with everything present it only runs dpkg-query and exits 0.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
list=${1:-$here/packages.txt}  # another list: deploy/cross/packages.txt (make cross)
mapfile -t wanted < <(grep -v '^\s*#' "$list" | sed '/^\s*$/d')

missing=()
for pkg in "${wanted[@]}"; do
  status=$(dpkg-query -W -f='${Status}' "$pkg" 2>/dev/null || true)
  [[ "$status" == "install ok installed" ]] || missing+=("$pkg")
done
if ((${#missing[@]} == 0)); then
  echo "install-deps: all ${#wanted[@]} packages present"
  exit 0
fi

echo "install-deps: installing ${#missing[@]} missing package(s): ${missing[*]}"
if [[ $(id -u) -eq 0 ]]; then
  sudo=()
elif command -v sudo >/dev/null && sudo -n true 2>/dev/null; then
  sudo=(sudo -n)
else
  echo "install-deps: need root to install: ${missing[*]}" >&2
  echo "install-deps: run 'sudo make deps' once, or install them with apt-get yourself" >&2
  exit 1
fi
export DEBIAN_FRONTEND=noninteractive
# Wait for another apt/dpkg run (a second build, unattended-upgrades) instead of failing on its lock.
lock=(-o DPkg::Lock::Timeout=900)
"${sudo[@]}" apt-get "${lock[@]}" update -qq
"${sudo[@]}" apt-get "${lock[@]}" install -y -qq --no-install-recommends "${missing[@]}"
echo "install-deps: done"
