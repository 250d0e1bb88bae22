#!/usr/bin/env bash
# Bevy against `relief render` for the three pipelines of relief's engine tests (three.js,
# Babylon.js): export each bundle (--target wgsl), render relief's frame at 128², have Bevy
# draw the bundle, print the difference. Run from anywhere; RELIEF names relief's binary
# (default: the workspace's target/release/relief), CARGO_TARGET_DIR this crate's build.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
relief="${RELIEF:-$here/../../target/release/relief}"
work="$(mktemp -d)"
export WGPU_BACKEND="${WGPU_BACKEND:-vulkan}"
cargo build --manifest-path "$here/Cargo.toml"
bevy="${CARGO_TARGET_DIR:-$here/target}/debug/relief-bevy"
status=0
i=0
for case in "linear(32)+binary(5)+shadow=soft(16)|scene:lion" "csm(64)|scene:rock_bump" "maxmip(96)|scene:shapes"; do
    pipe="${case%|*}"; scene="${case#*|}"
    "$relief" export "$pipe" --scene "$scene" --target wgsl --out "$work/bundle$i" > /dev/null 2>&1
    "$relief" render "$pipe" --scene "$scene" --size 128 --frames 1 --out "$work/render$i" > /dev/null
    "$bevy" "$work/bundle$i" "$work/render$i" "$work/bevy$i.png" 2> "$work/bevy$i.log" || { status=1; tail -5 "$work/bevy$i.log"; }
    i=$((i + 1))
done
echo "pictures and logs in $work"
exit $status
