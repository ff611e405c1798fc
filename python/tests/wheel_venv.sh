#!/bin/sh
# The package as users get it: build the wheel offline from this build (pip wheel
# --no-build-isolation), install it into a fresh virtual environment in a temporary folder, and
# from / (no PYTHONPATH, no source tree): import ramtk from the venv, run the examples, check them
# with mypy --strict against the shipped stubs, and read help(ramtk.scan)'s typed signature.
# The venv sees Debian's site-packages (--system-site-packages) for numpy: pip installs nothing
# from the network. Exit 77 (ctest: skipped) without Debian's venv, pip or mypy.
#   wheel_venv.sh PYTHON SOURCE_DIR BUILD_DIR
set -eu
python=$1 src=$2 build=$3
for m in venv pip wheel setuptools; do
  "$python" -c "import $m" 2>/dev/null || { echo "skipped: python3 module $m missing (scripts/setup.sh)"; exit 77; }
done
command -v mypy >/dev/null || { echo "skipped: mypy missing (scripts/setup.sh)"; exit 77; }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

cd "$src"
RAMTK_BUILD_DIR="$build" RAMTK_WHEEL_PREBUILT=1 "$python" -m pip wheel -q --no-build-isolation --no-deps --no-index \
  -w "$tmp/dist" .
wheel=$(ls "$tmp"/dist/ramtk-*.whl)
echo "built $(basename "$wheel")"
"$python" -m venv --system-site-packages "$tmp/venv"
"$tmp/venv/bin/python" -m pip install -q --no-index "$wheel"

cd /
unset PYTHONPATH
where=$("$tmp/venv/bin/python" -c 'import ramtk; print(ramtk.__file__)')
case "$where" in
  "$tmp/venv/"*) echo "import ramtk: $where" ;;
  *) echo "imported ramtk from $where, not from the venv"; exit 1 ;;
esac
for example in "$src"/python/examples/*.py; do
  name=$(basename "$example" .py)
  echo "== $name"
  "$tmp/venv/bin/python" "$example" --out "$tmp/$name"
done
mypy --strict --no-incremental --cache-dir "$tmp/mypy" --python-executable "$tmp/venv/bin/python" \
  "$src"/python/examples/*.py
"$tmp/venv/bin/python" - <<'PY'
import pydoc
import ramtk
text = pydoc.render_doc(ramtk.scan, renderer=pydoc.plaintext)
for want in ("radius: 'float' = 19.05", "progress: 'Optional[ProgressFn]'", "-> 'ScanResult'", "mm"):
    assert want in text, want
print("help(ramtk.scan): typed signature with units")
PY
echo "ok"
