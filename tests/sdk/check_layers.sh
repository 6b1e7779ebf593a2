#!/usr/bin/env bash
# The SDK by audience (docs/architecture.md "The SDK and the kit"), from the include lines:
#  - the element plugin API (sdk/include/mbd/sdk), the element plugins (plugins/joints,
#    plugins/forces, plugins/bodies) and the SDK's example (sdk/examples) include no mbd header
#    but the SDK's: never the formulation kit's (<mbd/kit/...>) nor the core's (<mbd/X.hpp>);
#  - the kit (kit/include, kit/src) includes the SDK's and its own, never the core's.
# Prints each offending line as FILE:LINE: TEXT and exits 1 when there is one.
# Usage: check_layers.sh SOURCE_DIR
#        check_layers.sh --self-test SOURCE_DIR   (the check refuses a kit include planted in
#                                                  an SDK header and in a joint plugin)
set -euo pipefail

# offending LAYER_FOLDERS... -- ALLOWED_REGEX: the mbd includes of the folders that the regex does not allow
offending() {
    local allowed=$1; shift
    local dirs=()
    for d in "$@"; do [ -d "$d" ] && dirs+=("$d"); done
    [ ${#dirs[@]} -gt 0 ] || return 0
    grep -rnE --include='*.hpp' --include='*.h' --include='*.cpp' '^\s*#\s*include\s*[<"]mbd/' "${dirs[@]}" |
        grep -vE "#\s*include\s*[<\"]mbd/($allowed)/" || true
}

check() {
    local root=$1 found
    cd "$root"
    found=$(offending sdk sdk/include sdk/examples plugins/joints plugins/forces plugins/bodies
            offending 'sdk|kit' kit/include kit/src)
    if [ -n "$found" ]; then
        echo "check_layers: an element-plugin header or plugin includes a kit or core header, or the kit a core header:"
        echo "$found"
        return 1
    fi
    [ -d sdk/include/mbd/sdk ] && [ -d kit/include/mbd/kit ] || { echo "check_layers: no sdk/ or kit/ under $root"; return 2; }
    echo "check_layers: the SDK, the element plugins and the kit include only their own layers"
}

self_test() {
    local source=$1 scratch
    scratch=$(mktemp -d)
    trap 'rm -rf "$scratch"' RETURN
    mkdir -p "$scratch/plugins"
    cp -r "$source/sdk" "$source/kit" "$scratch/"
    cp -r "$source/plugins/joints" "$scratch/plugins/"
    ( check "$scratch" >/dev/null ) || { echo "self-test: the unchanged copy must pass"; return 1; }
    local planted
    for planted in "sdk/include/mbd/sdk/joint.hpp:<mbd/kit/system.hpp>" "plugins/joints/revolute/revolute.cpp:<mbd/kit/formulation.hpp>" \
                   "kit/include/mbd/kit/system.hpp:<mbd/model.hpp>"; do
        local file=${planted%%:*} header=${planted#*:} out
        sed -i "1i #include $header" "$scratch/$file"
        if out=$( check "$scratch" ); then
            echo "self-test: $header planted in $file was not refused"; return 1
        fi
        echo "$out" | grep -qF "$file" || { echo "self-test: the refusal does not name $file: $out"; return 1; }
        cp "$source/$file" "$scratch/$file"
    done
    echo "self-test: every planted include was refused, naming its file"
}

if [ "${1:-}" = --self-test ]; then self_test "$2"; else check "$1"; fi
