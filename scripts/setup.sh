#!/usr/bin/env bash
# Installs everything the project needs on a fresh Debian bookworm machine:
# Debian packages (compilers, cmocka, ARM cross toolchain, QEMU, cppcheck,
# valgrind, clang and its sanitizer/libFuzzer runtime for tests/fuzz, Chromium
# for the HTML reports' browser test tests/e2e/test_report_browser.py) and a
# Python venv (.venv) from requirements.txt with the project's own package
# (the `aocs` CLI) installed into it. Idempotent and quick when
# everything is already there.
set -euo pipefail
cd "$(dirname "$0")/.."

APT_PACKAGES=(
  build-essential cmake ninja-build pkg-config
  libcmocka-dev libglib2.0-0 libglib2.0-dev
  gcc-arm-none-eabi libnewlib-arm-none-eabi binutils-arm-none-eabi
  qemu-system-arm
  cppcheck valgrind iproute2 util-linux
  clang libclang-rt-14-dev
  python3 python3-venv
  default-jdk-headless
  chromium
)

missing=()
for p in "${APT_PACKAGES[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done
if [ "${#missing[@]}" -gt 0 ]; then
  echo "setup: installing Debian packages: ${missing[*]}"
  SUDO=""
  if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi

PY=${AOCS_PYTHON:-python3}
stamp=.venv/.aocs-requirements
want=$(cat requirements.txt pyproject.toml | sha256sum | cut -d' ' -f1)
if [ ! -x .venv/bin/python ] || [ "$(cat "$stamp" 2>/dev/null)" != "$want" ]; then
  echo "setup: creating Python venv .venv from requirements.txt"
  "$PY" -m venv .venv
  .venv/bin/pip install -q --upgrade pip
  .venv/bin/pip install -q -r requirements.txt
  .venv/bin/pip install -q --no-deps -e .
  echo "$want" > "$stamp"
fi
