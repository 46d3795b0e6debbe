#!/usr/bin/env bash
# Assembles an Embree 4 folder (include/ + lib/) for building sturmray against
# Embree 4 on a machine whose packages give Embree 3 (Debian 12):
#   headers: Debian 13 ("trixie") libembree-dev, downloaded without installing it
#            and without touching the machine's apt configuration;
#   library: the official Embree 4 release build that PyPI's pyembree2 wheel ships
#            (libembree4.so.4 with its libtbb.so.12, found through RPATH $ORIGIN).
# Usage: tools/assemble_embree4.sh DEST   (idempotent; `make embree4` calls it)
set -euo pipefail

dest=${1:?usage: $0 DEST}
deb_version=${EMBREE4_DEB_VERSION:-4.3.3+dfsg-1}
wheel_version=${PYEMBREE2_VERSION:-1.0.1}

if [ -f "$dest/include/embree4/rtcore.h" ] && [ -f "$dest/lib/libembree4.so.4" ]; then
    echo "$dest already holds Embree 4"
    exit 0
fi

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mkdir -p "$work/lists/partial" "$work/deb"

# A private sources list and state: the machine's own apt setup stays untouched.
echo "deb http://deb.debian.org/debian trixie main" > "$work/sources.list"
apt_opts=(-o "Dir::Etc::SourceList=$work/sources.list" -o Dir::Etc::SourceParts=/dev/null
          -o "Dir::State::Lists=$work/lists" -o Debug::NoLocking=1 -o APT::Sandbox::User=root)
apt-get "${apt_opts[@]}" update -qq
(cd "$work/deb" && apt-get "${apt_opts[@]}" download "libembree-dev=$deb_version")
deb=$(ls "$work"/deb/libembree-dev_*.deb)
dpkg-deb -x "$deb" "$work/x"

python3 -m pip download --quiet --no-deps --only-binary=:all: --python-version 3.11 \
    -d "$work/wheel" "pyembree2==$wheel_version"
python3 -m zipfile -e "$work"/wheel/pyembree2-*.whl "$work/wheel/x"

mkdir -p "$dest/include" "$dest/lib"
rm -rf "$dest/include/embree4"
cp -r "$work/x/usr/include/embree4" "$dest/include/"
cp "$work/wheel/x/pyembree2/libembree4.so.4" "$work/wheel/x/pyembree2/libtbb.so.12" "$dest/lib/"
ln -sf libembree4.so.4 "$dest/lib/libembree4.so"
echo "assembled $dest: headers from $(basename "$deb"), library from pyembree2 $wheel_version"
