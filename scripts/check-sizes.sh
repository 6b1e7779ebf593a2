#!/usr/bin/env bash
# The size limits of the source (docs/contributing: no source file over 600 lines and no
# function over 80 lines outside tests), measured with Universal Ctags (function start and
# end lines). Prints every file and function over its limit as
#   file   PATH LINES
#   function PATH:LINE NAME LINES
# and exits 1 when one is not in the exceptions file (scripts/size-exceptions.txt: lines
# "function PATH NAME" or "file PATH", each a known offender awaiting its split) or an
# exception is no longer over its limit (remove it then). Usage: scripts/check-sizes.sh [ROOT]
set -euo pipefail
root=${1:-$(cd "$(dirname "$0")/.." && pwd)}
cd "$root"
max_file=600
max_function=80
exceptions=scripts/size-exceptions.txt

command -v ctags >/dev/null || { echo "check-sizes: ctags (universal-ctags) not found" >&2; exit 2; }
# the project's own sources: every folder but tests/, build trees and third-party code
mapfile -t files < <(git ls-files --cached --others --exclude-standard -- '*.cpp' '*.hpp' '*.h' '*.cc' | grep -Ev '^(tests|build[^/]*|third_party|external)/' || true)
[ ${#files[@]} -gt 0 ] || { echo "check-sizes: no sources under $root" >&2; exit 2; }

report=$(mktemp)
trap 'rm -f "$report"' EXIT
for f in "${files[@]}"; do
    n=$(wc -l < "$f")
    [ "$n" -gt "$max_file" ] && echo "file $f $n" >> "$report"
done
ctags --languages=C++ --kinds-C++=f --fields=+ne -f - "${files[@]}" 2>/dev/null |
    awk -F'\t' -v max="$max_function" '{
        line = ""; end = "";
        for (i = 4; i <= NF; ++i) {
            if ($i ~ /^line:/) line = substr($i, 6);
            if ($i ~ /^end:/) end = substr($i, 5);
        }
        if (line != "" && end != "" && end - line + 1 > max) print "function " $2 ":" line " " $1 " " (end - line + 1);
    }' | sort -u >> "$report"

status=0
while read -r kind where rest; do
    if [ "$kind" = file ]; then key="file $where"; else key="function ${where%%:*} ${rest%% *}"; fi
    if grep -qxF "$key" "$exceptions" 2>/dev/null; then
        echo "known   $kind $where $rest"
    else
        echo "OVER    $kind $where $rest"
        status=1
    fi
done < "$report"
if [ -f "$exceptions" ]; then
    while read -r kind path name; do
        case "$kind" in ''|'#'*) continue ;; esac
        if [ "$kind" = file ]; then
            grep -q "^file $path " "$report" || { echo "FIXED   file $path: remove it from $exceptions"; status=1; }
        else
            grep -qE "^function $path:[0-9]+ $name " "$report" ||
                { echo "FIXED   function $path $name: remove it from $exceptions"; status=1; }
        fi
    done < "$exceptions"
fi
[ "$status" -eq 0 ] && echo "check-sizes: every file within $max_file lines and every function within $max_function (known exceptions listed above)"
exit "$status"
