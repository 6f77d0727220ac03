#!/usr/bin/env bash
# CTest driver for the Blender add-on's headless test (wisp_hair_import_test.py beside this
# file). Exits 77, which CTest reports as skipped, when Blender is not installed. Installs
# nothing; Blender's user scripts (where the test installs the add-on) go to WORK_DIR.
#   run_blender_test.sh ADDON.py WISP_EXE WORK_DIR
set -euo pipefail
addon=$1
wisp=$2
work=$3
blender=${BLENDER:-blender}
if ! command -v "$blender" >/dev/null; then
  echo "SKIPPED: '$blender' is not installed (scripts/setup installs Debian's blender and" \
    "python3-numpy)"
  exit 77
fi
rm -rf "$work"
mkdir -p "$work"
export BLENDER_USER_SCRIPTS="$work/user_scripts"
exec "$blender" -b --factory-startup --python-exit-code 1 \
  --python "$(dirname "$0")/wisp_hair_import_test.py" -- "$addon" "$wisp" "$work"
