#!/usr/bin/env bash
# The fuzzing smoke test (issue 57), as CTest runs it:
#   run_fuzz_smoke.sh build BUILD_DIR
#   run_fuzz_smoke.sh run BUILD_DIR TARGET SECONDS
# `build` configures and builds this folder's project with clang++
# (libFuzzer + AddressSanitizer) into BUILD_DIR. `run` writes small valid
# inputs as the seed corpus of TARGET (ply_header, yaml_precheck, tum_list,
# camera_yaml, bag_messages),
# fuzzes it for SECONDS and fails on any finding, printing the input that
# caused it (as hex) so it can be made a test.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
mode=$1 build=$2

if [ "$mode" = build ]; then
  clang=$(command -v clang++ || true)
  if [ -z "$clang" ]; then
    echo "fuzz: clang++ not found (scripts/install-deps.sh installs clang and libclang-rt-14-dev)" >&2
    exit 1
  fi
  cmake -S "$here" -B "$build" -DCMAKE_CXX_COMPILER="$clang" -DCMAKE_BUILD_TYPE=None >/dev/null
  exec cmake --build "$build" -j1
fi

target=$3 seconds=$4
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
seeds="$work/seeds" corpus="$work/corpus"
mkdir -p "$seeds" "$corpus"
case "$target" in
  ply_header)
    printf 'ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\nproperty float z\nproperty uchar red\nproperty uchar green\nproperty uchar blue\nend_header\n0 0 0 255 0 0\n1 2 3 0 255 0\n' >"$seeds/ascii.ply"
    { printf 'ply\nformat binary_little_endian 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\nend_header\n'
      printf '\x00\x00\x80\x3f\x00\x00\x00\x40\x00\x00\x40\x40'; } >"$seeds/binary.ply"
    { printf 'ply\nformat binary_little_endian 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\n'
      printf 'element camera 1\nproperty float view_px\nproperty float view_py\nproperty float view_pz\nproperty int viewport_u\nproperty int viewport_v\nend_header\n'
      printf '\x00\x00\x80\x3f\x00\x00\x00\x40\x00\x00\x40\x40'
      printf '\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x01\x00\x00\x00\x01\x00\x00\x00'; } >"$seeds/camera.ply"
    ;;
  yaml_precheck)
    printf 'system:\n  bf: 40.0 # px*m\norb:\n  n_features: 1000\n  scale_factor: 1.2\ndynamic:\n  detector:\n    dynamic_classes: [person, "dog"]\n' >"$seeds/config.yaml"
    printf 'camera:\n  name: tum_fr1\n  width: 640\n  height: 480\n  fx: 517.3\n  fy: 516.5\n  cx: 318.6\n  cy: 255.3\n  k1: 0.26\n  depth_scale: 5000.0\n' >"$seeds/camera.yaml"
    printf -- '- - a\n  - b\n- {x: 1, y: [2, 3]}\nkey: ~\nother:\n  # all commented\n' >"$seeds/shapes.yaml"
    ;;
  camera_yaml)
    printf 'camera:\n  name: tum_fr1\n  width: 640\n  height: 480\n  fx: 517.3\n  fy: 516.5\n  cx: 318.6\n  cy: 255.3\n  k1: 0.2624\n  k2: -0.9531\n  p1: -0.0054\n  p2: 0.0026\n  k3: 1.1633\n  depth_scale: 5000.0\n' >"$seeds/tum_fr1.yaml"
    printf '# rendered\ncamera:\n  width: 320\n  height: 240\n  fx: 300\n  fy: 300\n  cx: 159.5\n  cy: 119.5\n  depth_scale: 1000\n' >"$seeds/small.yaml"
    printf 'camera: {width: 64, height: 48, fx: 50, fy: 50, cx: 31.5, cy: 23.5, depth_scale: 5000}\n' >"$seeds/flow.yaml"
    ;;
  tum_list)
    printf '# color images\n# timestamp filename\n1305031102.175304 rgb/1305031102.175304.png\n1305031102.211214 rgb/1305031102.211214.png\n1305031102.243211 rgb/1305031102.243211.png\n' >"$seeds/rgb.txt"
    printf '\xef\xbb\xbf1.0 depth/1.png\r\n2.5 depth/2.png\r\n' >"$seeds/bom_crlf.txt"
    ;;
  bag_messages)
    # A kind byte (0 RGB Image, 1 depth Image, 2 CompressedImage, 3 CameraInfo),
    # then the message as ROS serialises it (little-endian, u32-prefixed
    # strings and arrays): a 2x2 image of each encoding, a 1x1 PNG, TUM's fr1 camera.
    python3 - "$seeds" <<'PY'
import struct, sys, binascii
d = sys.argv[1]
def s(b): return struct.pack('<I', len(b)) + b
header = struct.pack('<III', 7, 1305031102, 175304000) + s(b'/openni_rgb_optical_frame')
def image(enc, bpp, big=0):
    return header + struct.pack('<II', 2, 2) + s(enc) + struct.pack('<BI', big, 2 * bpp) + s(bytes(range(4 * bpp)))
png = binascii.unhexlify('89504e470d0a1a0a0000000d4948445200000001000000010802000000907753de'
                         '0000000c4944415408d763f8cfc0000003010100c9fe92ef0000000049454e44ae426082')
info = (header + struct.pack('<II', 480, 640) + s(b'plumb_bob') +
        struct.pack('<I5d', 5, 0.2624, -0.9531, -0.0054, 0.0026, 1.1633) +
        struct.pack('<9d', 517.3, 0, 318.6, 0, 516.5, 255.3, 0, 0, 1) +
        struct.pack('<9d', 1, 0, 0, 0, 1, 0, 0, 0, 1) +
        struct.pack('<12d', 517.3, 0, 318.6, 0, 0, 516.5, 255.3, 0, 0, 0, 1, 0) +
        struct.pack('<6IB', 0, 0, 0, 0, 0, 0, 0))
seeds = {'rgb8': b'\0' + image(b'rgb8', 3), 'mono8': b'\0' + image(b'mono8', 1),
         'depth16': b'\1' + image(b'16UC1', 2), 'depth16be': b'\1' + image(b'16UC1', 2, 1),
         'depth32': b'\1' + image(b'32FC1', 4), 'png': b'\2' + header + s(b'png') + s(png),
         'info': b'\3' + info}
for name, data in seeds.items():
    open(f'{d}/{name}.msg', 'wb').write(data)
PY
    ;;
  *) echo "fuzz: unknown target '$target'" >&2; exit 2 ;;
esac

echo "fuzz_$target: $seconds s from $(ls "$seeds" | wc -l) seeds"
status=0
LSAN_OPTIONS="suppressions=$here/lsan.supp:print_suppressions=0" "$build/fuzz_$target" -max_total_time="$seconds" -timeout=30 -rss_limit_mb=2048 \
  -max_len=4096 -print_final_stats=1 -artifact_prefix="$work/" "$corpus" "$seeds" \
  >"$work/log" 2>&1 || status=$?
tail -n 25 "$work/log"
if [ $status -ne 0 ]; then
  for a in "$work"/crash-* "$work"/leak-* "$work"/timeout-* "$work"/oom-*; do
    [ -e "$a" ] || continue
    echo "fuzz_$target: finding $(basename "$a"), input as hex:"
    od -An -tx1 -v "$a" | head -n 64
  done
  exit 1
fi
