#!/bin/sh
# The cost of importing the analysis (which imports verify.check, and with it the
# lowering pipeline) on this branch against a snapshot of main, each on its own tree:
#   git archive main | tar -x -C /tmp/main_snap
#   bench/bench_verify_import.sh /path/to/this/tree /tmp/main_snap
# z3 must not load: `python -c "import sys, osc2check.analysis; print('z3' in sys.modules)"`.
A=${1:-.}
B=${2:?a tree of main to compare with}
exec farm-bench -n 15 --vs "sh -c 'cd $B && PYTHONPATH=$B exec python -c \"import osc2check.analysis\"'" -- \
    sh -c "cd $A && PYTHONPATH=$A exec python -c 'import osc2check.analysis'"
