#!/usr/bin/env bash
# Installs the Debian 12 packages penumbra builds and tests with, skipping those already present.
# Works as root or through sudo.
set -euo pipefail

packages=(
    cmake ninja-build g++ pkg-config
    libembree-dev libtbb-dev
    libopenimageio-dev openimageio-tools libopenexr-dev libopencolorio-dev
    libcli11-dev nlohmann-json3-dev libtinyobjloader-dev zlib1g-dev libfmt-dev
    libgtest-dev libgmock-dev libbenchmark-dev
    python3 python3-numpy python3-openimageio python3-matplotlib
    embree-tools time  # bench/compare_pathtracer.py: Embree's pathtracer and GNU time
)
# penumbra submit's tests and benchmarks start a real single-node Slurm cluster
# (tests/support/slurm_cluster.sh): the scheduler's daemons and commands, and MUNGE for its auth.
slurm_packages=(slurm-wlm munge)
packages+=("${slurm_packages[@]}")

missing=()
for p in "${packages[@]}"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
    exit 0
fi

echo "penumbra: installing ${missing[*]}" >&2
sudo=""
if [ "$(id -u)" -ne 0 ]; then
    command -v sudo >/dev/null || { echo "penumbra: need root or sudo to install packages" >&2; exit 1; }
    sudo="sudo"
fi
export DEBIAN_FRONTEND=noninteractive
$sudo apt-get update -qq
$sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
