#!/usr/bin/env bash
# The documentation holds together: every relative link and image of every
# Markdown file of the source tree ([text](path), ![alt](path), outside
# code) names a file or folder that exists, and README.md stays a page a
# newcomer reads (300 lines at most; the manual is under docs/).
#
#   cli_docs.sh STRATA_EXE SHARED_MESH_DIR ASSETS_DIR BINARY_TEST_DIR
set -u
ROOT=$(cd "$3/.." && pwd)
fail=0
bad() { echo "FAIL: $*"; fail=1; }

lines=$(wc -l < "$ROOT/README.md")
[ "$lines" -le 300 ] || bad "README.md has $lines lines (at most 300: move the details to docs/)"

# The Markdown files of the tree, not those of build folders or test data.
mapfile -t files < <(cd "$ROOT" && find . \( -path ./build -o -path './build-*' -o -path ./.git \
                      -o -path ./tests/data -o -path ./shared \) -prune -o -name '*.md' -type f -print | sort)
[ "${#files[@]}" -ge 5 ] || bad "found only ${#files[@]} Markdown files under $ROOT"

nlinks=0
for f in "${files[@]}"; do
    dir=$(dirname "$ROOT/$f")
    # Outside fenced code blocks, without inline code spans, every ](target).
    while IFS=$'\t' read -r line target; do
        [ -n "$target" ] || continue
        case "$target" in
            http://*|https://*|mailto:*|'#'*) continue ;;
        esac
        path=${target%%#*}
        path=${path%% *}            # [t](path "title")
        nlinks=$((nlinks + 1))
        if [ "${path#/}" != "$path" ]; then
            bad "$f:$line: absolute link '$target' (links are relative to the file)"
        elif [ ! -e "$dir/$path" ]; then
            bad "$f:$line: link '$target' names nothing ($dir/$path does not exist)"
        fi
    done < <(awk '
        /^[ \t]*```/ { fence = !fence; next }
        fence { next }
        {
            s = $0
            gsub(/`[^`]*`/, "", s)
            while (match(s, /\]\([^)]*\)/)) {
                t = substr(s, RSTART + 2, RLENGTH - 3)
                printf "%d\t%s\n", NR, t
                s = substr(s, RSTART + RLENGTH)
            }
        }' "$ROOT/$f")
done

# The docs the README sends a newcomer to are there and linked.
for doc in docs/CLI.md docs/MODELLER.md docs/BAKING.md docs/ARCHITECTURE.md docs/TESTING.md bench/RESULTS.md; do
    [ -f "$ROOT/$doc" ] || bad "$doc is missing"
    grep -qF "]($doc" "$ROOT/README.md" || bad "README.md does not link $doc"
done
# The manual's images are shown somewhere.
for img in "$ROOT"/docs/images/*.png; do
    name=docs/images/$(basename "$img")
    grep -rqF --include='*.md' "images/$(basename "$img")" "$ROOT/README.md" "$ROOT/docs" ||
        bad "$name is not shown by any document"
done

[ "$fail" -eq 0 ] || exit 1
echo "cli_docs: ${#files[@]} Markdown files, $nlinks relative links resolve; README.md has $lines lines"
