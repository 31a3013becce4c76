#!/usr/bin/env bash
# CI for the VS Code extension: clean install, tests, package.
# Prints the test results and the .vsix size; exits non-zero on any failure.
#   bash vscode-extension/ci.sh
set -euo pipefail

cd "$(dirname "${BASH_SOURCE[0]}")"
started=$(date +%s)
mkdir -p out
log=out/ci-test.log
max_vsix_bytes=$((1024 * 1024))

step() { printf '\n==> %s\n' "$*"; }

step "npm ci"
npm ci --no-audit --no-fund

step "npm test"
set +e
npm test 2>&1 | tee "$log"
test_status=${PIPESTATUS[0]}
set -e

step "npm run package"
rm -f ./*.vsix
package_status=0
npm run package || package_status=$?

# ---- summary
assertions=$(cat test/grammar/*.test.osc | grep -cE '^#\s*(\^|<[-~])' || true)
assertion_files=$(ls test/grammar/*.test.osc | wc -l)
grammar_ok=$(grep -cE 'test\.osc run successful+y' "$log" || true)
unit_line() { grep -E "^ℹ $1 " "$log" | tail -1 | awk '{print $3}'; }

echo
echo "==> summary"
echo "grammar assertions : ${assertions} in ${assertion_files} files (${grammar_ok} files passed)"
echo "snapshots          :"
sed -n '/^snapshot results:/,$p' "$log" | grep -E '^  (ok|FAIL|skip) ' | sed 's/^/  /'
if [ -n "$(unit_line tests)" ]; then
  echo "unit tests         : $(unit_line tests) run, $(unit_line pass) passed, $(unit_line fail) failed, $(unit_line skipped) skipped"
else
  echo "unit tests         : not run (an earlier step of npm test failed)"
fi
if grep -q 'error TS' "$log"; then echo "typecheck          : FAILED"; elif [ "$test_status" -eq 0 ]; then echo "typecheck          : ok (tsc --noEmit, strict)"; fi
echo "npm test           : $([ "$test_status" -eq 0 ] && echo ok || echo "FAILED (exit $test_status)")"

status=0
[ "$test_status" -eq 0 ] || status=1
vsix=$(ls ./*.vsix 2>/dev/null | head -1 || true)
if [ "$package_status" -ne 0 ] || [ -z "$vsix" ]; then
  echo "package            : FAILED"
  status=1
else
  bytes=$(wc -c < "$vsix" | tr -d ' ')
  echo "package            : ${vsix#./} ${bytes} bytes ($(( (bytes + 1023) / 1024 )) KiB)"
  if [ "$bytes" -ge "$max_vsix_bytes" ]; then
    echo "package            : FAILED (larger than 1 MiB)"
    status=1
  fi
fi
echo "time               : $(( $(date +%s) - started )) s"
exit "$status"
