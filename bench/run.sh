#!/usr/bin/env bash
# The benchmark suite in one command: pvrt against POV-Ray 3.7 on the same scenes, object
# scaling, parallel speedup. See bench/README.md; `bench/run.sh --help` lists the options.
#   bench/run.sh                 full run into bench/results/<date-time>/
#   bench/run.sh --quick         smoke test (tiny sizes, under 2 minutes)
# Runs bench/bench.py with a python3 that has matplotlib when there is one ($PVRT_PYTHON,
# then Debian's /usr/bin/python3, then python3 on the PATH); without it there are no plots.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
python=${PVRT_PYTHON:-}
if [ -z "$python" ]; then
  for candidate in /usr/bin/python3 python3; do
    if "$candidate" -c 'import matplotlib' >/dev/null 2>&1; then python=$candidate; break; fi
  done
fi
exec "${python:-python3}" "$here/bench.py" "$@"
