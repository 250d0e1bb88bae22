#!/usr/bin/env bash
# Bevy against `relief render` for the three pipelines and scenes of relief's engine tests
# (three.js, Babylon.js), then the same pipelines on scene:rocks: export each bundle for
# Bevy 0.19's material group (--target wgsl --group 3 --import-path relief::bundle), render
# relief's frame at 128², have Bevy draw the bundle, print the
# difference; exit 1 when a case misses the bar or fails. Run from anywhere; RELIEF names
# relief's binary (default: the workspace's target/release/relief), CARGO_TARGET_DIR this
# crate's build.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
relief="${RELIEF:-$here/../../target/release/relief}"
work="$(mktemp -d)"
export WGPU_BACKEND="${WGPU_BACKEND:-vulkan}"
cargo build --manifest-path "$here/Cargo.toml"
bevy="${CARGO_TARGET_DIR:-$here/target}/debug/relief-bevy"
status=0
i=0
cases=("linear(32)+binary(5)+shadow=soft(16)|scene:lion" "csm(64)|scene:rock_bump" "maxmip(96)|scene:shapes")
# The same three on rocks, whose albedo is a 1x1 map (Bevy loads it as a 1D texture).
cases+=("linear(32)+binary(5)+shadow=soft(16)|scene:rocks" "csm(64)|scene:rocks" "maxmip(96)|scene:rocks")
for case in "${cases[@]}"; do
    pipe="${case%|*}"; scene="${case#*|}"
    "$relief" export "$pipe" --scene "$scene" --target wgsl --group 3 --import-path relief::bundle --out "$work/bundle$i" > /dev/null 2>&1
    "$relief" render "$pipe" --scene "$scene" --size 128 --frames 1 --out "$work/render$i" > /dev/null
    echo -n "$scene: "
    "$bevy" "$work/bundle$i" "$work/render$i" "$work/bevy$i.png" 2> "$work/bevy$i.log" || { status=1; grep -v XDG_RUNTIME_DIR "$work/bevy$i.log" | tail -3; }
    i=$((i + 1))
done
echo "pictures and logs in $work"
exit $status
