#!/usr/bin/env bash
# Installs the Debian packages of debian-packages.txt that are missing. As root it runs
# apt-get itself; otherwise it prints the exact command and fails, so nothing half-builds.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
mapfile -t wanted < <(grep -v '^\s*#' "$here/debian-packages.txt" | sed '/^\s*$/d')

missing=()
for pkg in "${wanted[@]}"; do
  status=$(dpkg-query -W -f='${Status}' "$pkg" 2>/dev/null || true)
  [[ "$status" == "install ok installed" ]] || missing+=("$pkg")
done
[[ ${#missing[@]} -eq 0 ]] && exit 0

cmd="apt-get install -y --no-install-recommends ${missing[*]}"
if [[ $(id -u) -ne 0 ]]; then
  echo "Missing Debian packages. Install them with:" >&2
  echo "  sudo apt-get update && sudo $cmd" >&2
  exit 1
fi
echo "Installing ${#missing[@]} Debian packages: ${missing[*]}" >&2
export DEBIAN_FRONTEND=noninteractive
# A fresh machine may have no package lists yet; refresh once if the install cannot resolve.
if ! $cmd >/tmp/rtabmap_apt.log 2>&1; then
  apt-get update >>/tmp/rtabmap_apt.log 2>&1
  $cmd >>/tmp/rtabmap_apt.log 2>&1 || { tail -30 /tmp/rtabmap_apt.log >&2; exit 1; }
fi
