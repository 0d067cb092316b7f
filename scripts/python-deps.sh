#!/usr/bin/env bash
# Installs what the Python package and its tests need, from Debian only
# (python3-numpy, python3-cffi, python3-pytest, python3-setuptools,
# python3-matplotlib for the figures (treetrace.plots) and the tutorial,
# python3-pip), when missing. Runs apt-get as root, or through sudo.
set -euo pipefail
packages=(python3 python3-numpy python3-pytest python3-setuptools python3-pip python3-wheel
          python3-matplotlib)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ "${#missing[@]}" -gt 0 ]; then
  echo "python-deps: installing ${missing[*]}" >&2
  sudo=""
  [ "$(id -u)" -eq 0 ] || sudo="sudo"
  export DEBIAN_FRONTEND=noninteractive
  $sudo apt-get update -qq
  $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >&2
fi
