#!/usr/bin/env bash
# Installs the Pteromys add-on into FreeCAD's Mod folder (FreeCAD 0.20).
#
#   freecad_workbench/install.sh [--mod-dir DIR] [--python-path DIR] [--uninstall]
#
# --mod-dir      where FreeCAD looks for add-ons; default: $FREECAD_USER_HOME/Mod
#                when that variable is set, else ~/.local/share/FreeCAD/Mod.
#                (/usr/share/freecad/Mod works too, for all users, as root.)
# --python-path  folder holding the engine package `pteromys` (a build's
#                `python` folder); default: <repository>/build/python. Written
#                to Mod/Pteromys/pteromys.cfg, read when the add-on first needs
#                the engine. Not needed when `pteromys` is installed system-wide
#                (cmake --install build, into /usr/local/lib/python3/dist-packages).
#
# The add-on is copied (not linked), so later edits of the source tree need a
# new install. Idempotent: reinstalling replaces the previous copy atomically.
set -euo pipefail
SRC=$(cd "$(dirname "$0")" && pwd)
ROOT=$(cd "$SRC/.." && pwd)

if [ -n "${FREECAD_USER_HOME:-}" ]; then
  MOD_DIR="$FREECAD_USER_HOME/Mod"
else
  MOD_DIR="${XDG_DATA_HOME:-$HOME/.local/share}/FreeCAD/Mod"
fi
PY_PATH="$ROOT/build/python"
UNINSTALL=0
while [ $# -gt 0 ]; do
  case "$1" in
    --mod-dir) MOD_DIR="$2"; shift 2 ;;
    --python-path) PY_PATH="$2"; shift 2 ;;
    --uninstall) UNINSTALL=1; shift ;;
    -h|--help) sed -n '2,18p' "$0"; exit 0 ;;
    *) echo "install.sh: unknown option '$1' (try --help)" >&2; exit 2 ;;
  esac
done

DEST="$MOD_DIR/Pteromys"
if [ "$UNINSTALL" = 1 ]; then
  rm -rf "$DEST"
  echo "install.sh: removed $DEST"
  exit 0
fi

PY_PATH=$(cd "$PY_PATH" 2>/dev/null && pwd || echo "$PY_PATH")
if [ ! -f "$PY_PATH/pteromys/__init__.py" ]; then
  echo "install.sh: warning: no engine package at $PY_PATH/pteromys (build it first: cmake --build build);" \
       "the workbench will say so until it exists" >&2
fi

mkdir -p "$MOD_DIR"
TMP=$(mktemp -d "$MOD_DIR/.Pteromys.XXXXXX")
trap 'rm -rf "$TMP"' EXIT
( cd "$SRC" && tar --exclude='__pycache__' --exclude='*.pyc' --exclude='pteromys.cfg' --exclude='install.sh' -cf - . ) | ( cd "$TMP" && tar -xf - )
/usr/bin/python3 - "$TMP/pteromys.cfg" "$PY_PATH" "$ROOT" <<'PY'
import json, sys
with open(sys.argv[1], "w") as f:
    json.dump({"python_path": sys.argv[2], "source": sys.argv[3]}, f, indent=1)
PY
chmod -R u+rwX,go+rX "$TMP"
rm -rf "$DEST"
mv "$TMP" "$DEST"
trap - EXIT
echo "install.sh: installed the Pteromys workbench in $DEST (engine: $PY_PATH)"
