#!/bin/sh
# The cost of importing the analysis (which imports verify.check, and with it the
# lowering pipeline) on this branch against a snapshot of main, each on its own tree,
# the two run in turn (B A B A ...) so that the machine's drift touches both alike:
#   git archive main | tar -x -C /tmp/main_snap
#   bench/bench_verify_import.sh /path/to/this/tree /tmp/main_snap
# Prints one line per run: the tree (A this one, B main) and its wall and user seconds.
# z3 must not load: `python -c "import sys, osc2check.analysis; print('z3' in sys.modules)"`.
A=$(cd "${1:-.}" && pwd)
B=$(cd "${2:?a tree of main to compare with}" && pwd)
for i in $(seq 15); do
    for side in B A; do
        if [ "$side" = A ]; then tree=$A; else tree=$B; fi
        (cd "$tree" && PYTHONPATH=$tree /usr/bin/time -f "$side %e s wall %U s user" \
            python -c "import osc2check.analysis")
    done
done
