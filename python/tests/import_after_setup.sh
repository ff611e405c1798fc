#!/bin/sh
# After scripts/setup.sh, Debian's python3 imports ramtk without PYTHONPATH: setup.sh writes a
# ramtk-build.pth naming the build's python/ folder into the interpreter's site-packages.
# Exit 77 (ctest: skipped) on a build that setup.sh did not make.
#   import_after_setup.sh PYTHON BUILD_PYTHON_DIR VERSION
python=$1 dir=$2 version=$3
site=$("$python" -c 'import sysconfig; print(sysconfig.get_paths()["purelib"])')
if ! grep -qx "$dir" "$site/ramtk-build.pth" 2>/dev/null; then
  echo "skipped: $site/ramtk-build.pth does not name $dir (run scripts/setup.sh)"
  exit 77
fi
got=$(cd / && env -u PYTHONPATH "$python" -c 'import ramtk; print(ramtk.__version__)') || exit 1
[ "$got" = "$version" ] || { echo "imported version $got, expected $version"; exit 1; }
echo "import ramtk: $got"
