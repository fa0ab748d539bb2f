#!/usr/bin/env bash
# Builds the Debian package from build/ (cpack -G DEB), installs it, renders
# two frames and analyzes nothing else from /tmp (outside the source tree, so
# the tools must find their data under /usr/share/aar), opens them with the
# installed Python reader, then removes it again.
# Usage: bash scripts/test-package.sh   (as root, or with sudo; after scripts/build.sh)
set -euo pipefail
cd "$(dirname "$0")/.."
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi

rm -f build/aar-stereo_*.deb
(cd build && cpack -G DEB >/dev/null)
deb=$(ls "$PWD"/build/aar-stereo_*.deb)
echo "test-package: built $(basename "$deb")"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get install -y -q --no-install-recommends "$deb" >/dev/null
trap '$SUDO dpkg --purge aar-stereo >/dev/null' EXIT

work=$(mktemp -d /tmp/aar-package-test.XXXXXX)
cd "$work"
/usr/bin/aar-render --version
/usr/bin/aar-analyze --version
/usr/bin/aar-render render "$work/two" --frames 600:602 --msaa 1 --no-progress
test -f "$work/two/frames/000601_left.png"
test -f "$work/two/frames/000600.json"
# The thesis geometry and the distorted lens, from the installed data.
/usr/bin/aar-render render "$work/thesis" --rig /usr/share/aar/scenes/rig-thesis.json \
    --flight-path /usr/share/aar/flightpaths/conops-level.csv --frames 0:1 --msaa 1 --no-progress
/usr/bin/aar-render render "$work/lens" --rig /usr/share/aar/scenes/rig-distorted.json --frames 600:601 --msaa 1 \
    --no-progress
test -f "$work/thesis/frames/000000_left.png"
test -f "$work/lens/frames/000600_left.png"
/usr/bin/aar-analyze reference --model full --points 1000 --out "$work/full.ply" >/dev/null
# The Python reader, from the installed package (-B: no byte code left in /usr/lib for dpkg --purge to trip on).
/usr/bin/python3 -B -c "
import aar_stereo
d = aar_stereo.open_dataset('two')
assert aar_stereo.__file__.startswith('/usr/lib/python3/dist-packages/'), aar_stereo.__file__
assert [f.index for f in d] == [600, 601] and d[1].left().shape == (768, 1024, 3), d
"
cd /
rm -rf "$work"
echo "test-package: installed package renders from /tmp, its Python reader opens the renders"
