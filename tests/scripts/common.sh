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
