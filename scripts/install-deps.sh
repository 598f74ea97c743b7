#!/usr/bin/env bash
# Installs the Debian packages meadow needs, only those missing: the Vulkan loader and headers,
# lavapipe (mesa-vulkan-drivers), glslang, the Khronos validation layer, and Xvfb for the viewer
# tests. Uses sudo when not root. Safe to run again: it does nothing when all are present.
set -euo pipefail

packages=(libvulkan1 libvulkan-dev mesa-vulkan-drivers glslang-tools vulkan-validationlayers xvfb xauth)

missing=()
for pkg in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$pkg" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$pkg")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  exit 0
fi

if ! command -v apt-get >/dev/null 2>&1; then
  echo "error: missing packages (${missing[*]}) and no apt-get: install them with your package manager" >&2
  exit 1
fi

sudo=()
if [ "$(id -u)" -ne 0 ]; then
  if command -v sudo >/dev/null 2>&1; then
    sudo=(sudo)
  else
    echo "error: missing packages (${missing[*]}); run as root or install sudo" >&2
    exit 1
  fi
fi

echo "installing: ${missing[*]}"
"${sudo[@]}" apt-get update -qq
DEBIAN_FRONTEND=noninteractive "${sudo[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"
