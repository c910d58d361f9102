# SPDX-License-Identifier: MIT
# Shared by the tests/scripts/test_*.sh scripts (sourced, not a test).
# missing MSG: a required tool is absent. In CI (CI=true) that is a
# failure; elsewhere the test is skipped (exit 77, ctest SKIP_RETURN_CODE).
# Uses the caller's $name for the message prefix.
missing() {
  if [ "${CI:-}" = "true" ]; then
    echo "${name:-test}: FAIL: $* (required in CI)" >&2
    exit 1
  fi
  echo "${name:-test}: SKIP: $*"
  exit 77
}

# cli_setup NAME BUILD_DIR SOURCE_DIR: the preamble of the CLI scripts
# (bash): sets $name, $sfit, $data and a temporary directory $tmp removed on
# exit, requires /usr/bin/python3, and defines fail MSG, py CODE ARGS
# (python3 with tests/scripts on the path) and expect_rc CODE CMD... (runs
# CMD, checks its exit status, keeps its stdout in $out and status in $rc).
cli_setup() {
  name=$1
  sfit="$2/bin/sfit"
  data="$3/tests/data"
  cli_src=$3
  tmp=$(mktemp -d)
  trap 'rm -rf "$tmp"' EXIT
  [ -x /usr/bin/python3 ] || missing "/usr/bin/python3 not found"
  fail() { echo "FAIL: $*" >&2; exit 1; }
  py() { PYTHONPATH="$cli_src/tests/scripts" /usr/bin/python3 -c "$@"; }
  expect_rc() {
    local want=$1; shift
    set +e
    out=$("$@" 2>"$tmp/stderr"); rc=$?
    set -e
    [ "$rc" -eq "$want" ] || fail "'$*': exit $rc, expected $want; stdout: $out; stderr: $(cat "$tmp/stderr")"
  }
}
