#!/usr/bin/env bash
# The paper's experiments in one command (bench/README.md, "The paper"):
#   bench/paper.sh               default sizes (640x400, P up to nproc): under 10 minutes on 2 cores
#   bench/paper.sh --full        the paper's sizes (1280x800, c up to 256) and every compiler of table 1
#   bench/paper.sh --quick       tiny sizes (the ctest smoke test; its numbers mean nothing)
# Writes bench/results/paper-<date-time>/ (or --out DIR): report.md, a PNG per figure, a CSV of every run.
# Runs bench/paper.py with a python3 that has numpy and matplotlib: $PVRT_PYTHON, else Debian's
# /usr/bin/python3 (a pyenv shim on the PATH may lack them).
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
python=${PVRT_PYTHON:-}
if [ -z "$python" ]; then
  for candidate in /usr/bin/python3 python3; do
    if "$candidate" -c 'import numpy, matplotlib' >/dev/null 2>&1; then python=$candidate; break; fi
  done
fi
if [ -z "$python" ]; then
  echo "bench/paper.sh: no python3 with numpy and matplotlib (apt-get install python3-matplotlib)" >&2
  exit 2
fi
# mpirun and the scripts' own children find Debian's python3 first.
export PATH="/usr/bin:$PATH"
exec "$python" "$here/paper.py" "$@"
