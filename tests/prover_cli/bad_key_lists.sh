#!/usr/bin/env bash
# bad_key_lists: the provers refuse a --keys list they cannot honour.
#
#   bad_key_lists.sh WARPMESH-PROVE-BCC WARPMESH
#
# Before 2026-12-06 `warpmesh prove --keys 99999` crashed (SIGSEGV: the index
# was used unchecked) and `warpmesh-prove-bcc --keys 99999` exited 0 with a
# certificate of no keys claiming 90°/90°; a token like "x" proved key 0.
# Now every bad list (out of range, negative, not a number, empty, a trailing
# comma) exits 2 with a message naming the option and the bad token, and
# writes no file.
set -uo pipefail
prove_bcc="$1" warpmesh="$2"
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
failed=0
expect_refused() {  # NAME OUTPUT COMMAND...
  local name="$1" out="$2"
  shift 2
  "$@" >"$tmp/out.log" 2>"$tmp/err.log"
  local rc=$?
  if [ "$rc" -ne 2 ] || ! grep -q -- "--keys expects key indices" "$tmp/err.log" || [ -e "$out" ]; then
    echo "bad_key_lists: $name: exit $rc, stderr: $(head -c 200 "$tmp/err.log"), output $( [ -e "$out" ] && echo written || echo absent)" >&2
    failed=1
  fi
  rm -rf "$out"
}
for keys in 99999 -1 x 1,x "" 3, 1,,2; do
  expect_refused "warpmesh-prove-bcc --keys '$keys'" "$tmp/bcc.cert" "$prove_bcc" --threads 1 --keys "$keys" --out "$tmp/bcc.cert"
  expect_refused "warpmesh prove --keys '$keys'" "$tmp/2d" "$warpmesh" prove --rule maxmin --threads 1 --keys "$keys" --out "$tmp/2d"
done
# A good list still proves.
"$prove_bcc" --threads 1 --keys 0,5 --out "$tmp/ok.cert" 2>/dev/null && grep -q '^keys 2$' "$tmp/ok.cert" ||
  { echo "bad_key_lists: warpmesh-prove-bcc --keys 0,5 did not prove two keys" >&2; failed=1; }
[ "$failed" -eq 0 ] && echo "bad_key_lists: ok"
exit "$failed"
