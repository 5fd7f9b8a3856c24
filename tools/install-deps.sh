#!/usr/bin/env bash
# Installs what pvrt needs to build, test and compare against POV-Ray (Debian 12, as
# root). Does nothing when everything is already there.
set -euo pipefail
packages=(
  build-essential cmake pkg-config
  libtinyxml2-dev libpng-dev libopenimageio-dev openimageio-tools libfmt-dev libcli11-dev libssl-dev nlohmann-json3-dev
  libgtest-dev libomp-dev
  libopenmpi-dev openmpi-bin
  povray
  clang libclang-rt-14-dev
  python3-matplotlib
)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q 'install ok installed' || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "install-deps: installing ${missing[*]}"
  sudo=""
  [ "$(id -u)" -eq 0 ] || sudo="sudo"
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi
