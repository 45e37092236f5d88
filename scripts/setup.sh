#!/usr/bin/env bash
# Installs the system packages tetrasim needs on Debian/Ubuntu, skipping what is present:
#   Vulkan loader + lavapipe (Mesa's CPU Vulkan driver) + the Khronos validation layer,
#   and cmake / python3 / a C++ compiler for building shaderc and TetGen from source;
#   then a Python venv at target/py with meshio 5.3.5, which tests/mesh_readers.rs uses to
#   check that meshio reads our TetGen files (scripts/test.sh points TETRASIM_PYTHON at it).
set -euo pipefail

packages=(libvulkan1 mesa-vulkan-drivers vulkan-validationlayers cmake python3 python3-venv g++ git)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "setup: installing ${missing[*]}" >&2
  SUDO=""
  [ "$(id -u)" -eq 0 ] || SUDO="sudo"
  $SUDO apt-get update -q
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -q --no-install-recommends "${missing[@]}"
fi
command -v cargo >/dev/null || { echo "setup: cargo not found; install Rust (rustup) first" >&2; exit 1; }
# scripts/test.sh runs clippy first.
if ! cargo clippy --version >/dev/null 2>&1; then
  echo "setup: installing clippy" >&2
  rustup component add clippy
fi
venv="$(dirname "$0")/../target/py"
if ! "$venv/bin/python" -c "import meshio" 2>/dev/null; then
  echo "setup: creating $venv with meshio 5.3.5" >&2
  rm -rf "$venv"
  python3 -m venv "$venv"
  "$venv/bin/pip" install -q "meshio==5.3.5"
fi
