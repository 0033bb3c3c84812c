#!/usr/bin/env bash
# checker_endless_input: the checkers reject an endless or huge stream
# without holding it (before 2026-12-06 warpmesh-check-bcc read every line
# into memory first, and both read a line without newlines whole: a stream
# of "key a" lines or of bytes without a newline grew until memory ran out).
#
#   checker_endless_input.sh WARPMESH-CHECK WARPMESH-CHECK-BCC
#
# Each stream is cut at 400 MB so that a regression ends too; the checker
# must exit 1 naming the bound it hit, long before that.
set -uo pipefail
check2d="$1" check3d="$2"
failed=0
expect() {  # NAME MESSAGE COMMAND... (the stream on stdin, read as /dev/stdin; not in a pipeline, which would lose `failed`)
  local name="$1" msg="$2"
  shift 2
  local err rc
  err="$("$@" /dev/stdin 2>&1 >/dev/null)"
  rc=$?
  if [ "$rc" -ne 1 ] || ! grep -q -- "$msg" <<<"$err"; then
    echo "checker_endless_input: $name: exit $rc, stderr: ${err:0:200}" >&2
    failed=1
  fi
}
expect "3D, no newline" "a line longer than 16 MB" "$check3d" < <(yes a | tr -d '\n' | head -c 400M)
expect "3D, endless key lines" "more than 1000010 lines" "$check3d" < <(yes "key a" | head -c 400M)
expect "3D, endless blank lines" "larger than 256 MB" "$check3d" < <(yes "" | head -c 400M)
expect "2D, no newline" "certificate too large" "$check2d" < <(yes a | tr -d '\n' | head -c 400M)
expect "2D, endless key lines" "certificate too large" "$check2d" < <(yes "key a" | head -c 400M)
[ "$failed" -eq 0 ] && echo "checker_endless_input: ok"
exit "$failed"
