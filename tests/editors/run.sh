#!/usr/bin/env bash
# One entry point for the editor-support tests (VS Code grammar/extension and Vim syntax).
# Needs node + npm (Debian: nodejs, npm) and vim with +syntax (Debian: vim).
# Exits non-zero if any part fails.
set -u
cd "$(dirname "${BASH_SOURCE[0]}")" || exit 1

status=0

if [ ! -d node_modules/vscode-textmate ] || [ ! -d node_modules/vscode-oniguruma ]; then
  echo "run.sh: npm ci --no-audit --no-fund (in $(pwd))"
  if ! npm ci --no-audit --no-fund; then
    echo "run.sh: npm ci failed" >&2
    exit 1
  fi
fi

echo "run.sh: node --test (in $(pwd))"
if ! node --test; then
  echo "run.sh: node --test FAILED" >&2
  status=1
fi

echo "run.sh: bash vim_syntax.sh"
if ! bash ./vim_syntax.sh; then
  echo "run.sh: vim_syntax.sh FAILED" >&2
  status=1
fi

if [ "$status" -eq 0 ]; then
  echo "run.sh: all editor tests passed"
else
  echo "run.sh: editor tests FAILED" >&2
fi
exit "$status"
