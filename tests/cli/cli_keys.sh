#!/usr/bin/env bash
# `strata --keys` prints the key table generated from the modeller's action
# table (ui/actions.c), and docs/MODELLER.md holds exactly that table
# (tests/ui/test_actions.c checks the same through the library).
#
#   cli_keys.sh STRATA_EXE SHARED_MESH_DIR ASSETS_DIR BINARY_TEST_DIR
set -u
EXE=$1 ASSETS=$3
DOC="$ASSETS/../docs/MODELLER.md"
[ -f "$DOC" ] || { echo "FAIL: $DOC is missing"; exit 1; }
out=$("$EXE" --keys 2>&1); rc=$?
if [ "$rc" -eq 2 ] && grep -q "built without the modeller window" <<<"$out"; then
    echo "cli_keys: strata was built without the window: nothing to compare"
    exit 0
fi
[ "$rc" -eq 0 ] || { echo "FAIL: strata --keys exited $rc: $out"; exit 1; }
begin=$(head -1 <<<"$out")
end=$(tail -1 <<<"$out")
case "$begin" in "<!-- keys:"*) ;; *) echo "FAIL: strata --keys does not start with the key-table marker: $begin"; exit 1 ;; esac
for key in '`Ctrl+D`' '`Ctrl+Shift+D`' '`Ctrl+Alt+D`' '`F1`' '`Numpad 1`' '`Shift+PageUp`' '`K`'; do
    grep -qF -- "$key" <<<"$out" || { echo "FAIL: strata --keys lacks $key"; exit 1; }
done
section=$(awk -v b="$begin" -v e="$end" '$0 == b { on = 1 } on { print } on && $0 == e { exit }' "$DOC")
if [ "$section" != "$out" ]; then
    echo "FAIL: docs/MODELLER.md's key table differs from \`strata --keys\` (replace it by that output):"
    diff <(printf '%s\n' "$section") <(printf '%s\n' "$out") | head -20
    exit 1
fi
echo "cli_keys: docs/MODELLER.md's key table is strata --keys ($(grep -c '^| ' <<<"$out") rows)"
