#!/usr/bin/env bash
# Configures and builds softflow in ./build (Release).
set -euo pipefail
cd "$(dirname "$0")/.."
# The tests' Python is Debian's, which has numpy/scipy/matplotlib from
# install_deps.sh (another python3 first on PATH may lack them).
python=()
[[ -x /usr/bin/python3 ]] && python=(-DPython3_EXECUTABLE=/usr/bin/python3)
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release "${python[@]}"
cmake --build build -j "$(nproc)"
