#!/usr/bin/env bash
# Installs the peers of `make peers`, for the comparison only (never a
# dependency of sturmray): POV-Ray 3.7 and its samples from Debian, Mitsuba 3
# from PyPI in a venv of its own (.venv-peers), and Debian's LLVM 19 for
# Mitsuba's LLVM variants. Idempotent: installs only what is missing.
set -euo pipefail
cd "$(dirname "$0")/../.."

# Mitsuba's llvm_* variants JIT through the LLVM library Dr.Jit dlopens. With
# Debian 12's default (LLVM 14) the variant aborts; LLVM 19 works, and
# `make peers` points DRJIT_LIBLLVM_PATH at /usr/lib/x86_64-linux-gnu/libLLVM.so.19.1.
packages=(povray povray-examples povray-includes libllvm19 python3-venv)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "installing: ${missing[*]}"
  sudo=$( [ "$(id -u)" = 0 ] || echo sudo )
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq "${missing[@]}"
fi

venv=.venv-peers
stamp=$venv/.installed
if [ ! -f "$stamp" ] || [ tools/peers/requirements.txt -nt "$stamp" ]; then
  test -x $venv/bin/python || python3 -m venv $venv
  $venv/bin/python -m pip install -q -r tools/peers/requirements.txt
  touch "$stamp"
fi
