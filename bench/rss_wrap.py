#!/usr/bin/env python3
"""rss_wrap.py PREFIX COMMAND...: runs COMMAND and writes its peak resident set (KiB, getrusage of the child, what
`/usr/bin/time -v` calls Maximum resident set size) to PREFIX.<rank>, the rank from Open MPI's environment (0
outside mpirun). Started by mpirun in place of pvrt, it gives every rank's own peak, which mpirun's does not."""
import os
import subprocess
import sys

rank = os.environ.get("OMPI_COMM_WORLD_RANK", os.environ.get("PMI_RANK", "0"))
p = subprocess.Popen(sys.argv[2:])
_, status, usage = os.wait4(p.pid, 0)
with open("%s.%s" % (sys.argv[1], rank), "w") as f:
    f.write("%d\n" % usage.ru_maxrss)
sys.exit(os.waitstatus_to_exitcode(status))
