#!/usr/bin/env bash
# Installs every Debian 12 package the project needs to build, test and plot.
# Usage: bash scripts/install-deps.sh   (as root, or with sudo available)
set -euo pipefail

packages=(
  build-essential cmake ninja-build pkg-config git clang-format dpkg-dev
  clang libclang-rt-14-dev
  libvulkan-dev mesa-vulkan-drivers vulkan-tools glslang-tools
  libglm-dev libtinygltf-dev nlohmann-json3-dev
  libopenimageio-dev openimageio-tools
  libopencv-dev libeigen3-dev libpng-dev
  libcli11-dev libnanoflann-dev libgtest-dev libgmock-dev libssl-dev
  python3 python3-matplotlib python3-imath
  python3-numpy python3-pil python3-openimageio python3-opencv
  python3-rosbag python3-sensor-msgs python3-geometry-msgs python3-tf2-msgs
  chromium
  # tests/slurm: a one-node Slurm cluster that the test starts on its own key, socket and ports (Debian's
  # packages enable munge and slurmctld services; without slurm.conf slurmctld does not start)
  slurm-wlm munge
)

SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ "${#missing[@]}" -eq 0 ]; then
  echo "install-deps: all ${#packages[@]} packages already installed"
  exit 0
fi
echo "install-deps: installing ${#missing[@]} packages: ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -q
$SUDO apt-get install -y -q --no-install-recommends "${missing[@]}"
