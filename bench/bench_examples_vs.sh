#!/bin/sh
# Two example runs (the cut-in: vehicles; the NCAP pedestrian: a walker) with this tree's
# runner against another tree's (a snapshot of main), paired A B A B by farm-bench:
#   git archive main | tar -x -C /tmp/main_snap
#   bench/bench_examples_vs.sh /path/to/this/tree /tmp/main_snap
# Each tree's bytecode is cached apart (PYTHONPYCACHEPREFIX), so that neither compiles its
# sources on every run (a tree without __pycache__ under PYTHONDONTWRITEBYTECODE=1 would).
A=$(cd "${1:-.}" && pwd)
B=$(cd "${2:?a tree of main to compare with}" && pwd)
run() {
    echo "unset PYTHONDONTWRITEBYTECODE; export PYTHONPATH=$1 PYTHONPYCACHEPREFIX=/tmp/bench_pyc$1;" \
        "out=\$(mktemp -d); cd $1 &&" \
        "python -m osc2runner examples/cut_in_and_stop.osc --out \$out/a >/dev/null &&" \
        "python -m osc2runner examples/ncap_cpna25_pedestrian.osc --out \$out/b >/dev/null;" \
        "rc=\$?; rm -rf \$out; exit \$rc"
}
exec farm-bench -n 5 --timeout 600 --vs "sh -c '$(run "$B")'" -- sh -c "$(run "$A")"
