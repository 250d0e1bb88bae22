#!/usr/bin/env bash
# relief on a real GPU: Tables 4.5, 4.7 and 4.11 (256², as the dissertation's grids have
# them) and the `frontier` grid at 1024², each row with its adapter and driver, beside the GPU
# compiler's model (`gpu_*` columns, from costs.json: the figures `relief cost` wrote where
# Mesa's RADV is installed), and the reports that rank the model against this GPU's clock
# (Spearman's ρ per scene and view: "How the model orders the pipelines").
#
# Needs nothing but this repository and relief's release binary:
#
#   cargo build --release            # on any x86-64 Linux machine, then carry target/release/relief
#   docs/notes/gpu/run.sh OUT        # from the repository root, on the GPU machine
#
# When the machine has no Vulkan loader (`ldconfig -p` lists no libvulkan.so.1), the script
# unpacks the Debian packages in $DEBS (default .gl/; docs/notes/gpu/fetch-loader.sh downloads
# them once, on any Debian or Ubuntu machine with apt) under $OUT/loader and points the
# dynamic linker there: no root needed, nothing installed.
#
# Within $DEADLINE seconds (default 480, the 8 minutes the issue gives): the tables first,
# then the frontier for what time is left. A sweep stopped at the deadline keeps every cell it
# finished (rows are appended cell by cell) and the run says how many it measured; running
# the script again on the same OUT resumes.
#
# Knobs for a dry run on a machine without a GPU: ALLOW_CPU=1 (accept a software adapter),
# SIZE (the frontier's frame size, default 1024), TABLES (default "t4.5 t4.7 t4.11"), FRONTIER
# (default "frontier"), FRAMES (timed blocks per cell, default 50), RELIEF (the binary,
# default target/release/relief), COSTS (default docs/notes/gpu/costs.json), FORCE_LOADER=1
# (use the carried loader even where the machine has one).
set -euo pipefail

out=${1:?usage: docs/notes/gpu/run.sh OUT}
relief=${RELIEF:-target/release/relief}
costs=${COSTS:-docs/notes/gpu/costs.json}
debs=${DEBS:-.gl}
deadline=${DEADLINE:-480}
size=${SIZE:-1024}
tables=${TABLES:-t4.5 t4.7 t4.11}
frontier=${FRONTIER:-frontier}
frames=${FRAMES:-50}
start=$(date +%s)

say() { echo "run.sh: $*" >&2; }
die() { say "$*"; exit 1; }
left() { echo $((deadline - ($(date +%s) - start))); }

[ -x "$relief" ] || die "no relief binary at $relief (cargo build --release, or RELIEF=PATH)"
[ -f "$costs" ] || die "no compiler figures at $costs (relief cost --grid GRID --json FILE where RADV is installed)"
mkdir -p "$out"

# The Vulkan loader: the machine's own, else the carried Debian packages, unpacked under
# $out/loader (dpkg-deb where there is one, else ar and tar).
if [ "${FORCE_LOADER:-}" = 1 ] || ! ldconfig -p 2>/dev/null | grep -q 'libvulkan\.so\.1'; then
    shopt -s nullglob
    pkgs=("$debs"/*.deb)
    [ ${#pkgs[@]} -gt 0 ] || die "no Vulkan loader on this machine and no .deb files in $debs (docs/notes/gpu/fetch-loader.sh fetches them)"
    root="$out/loader"
    mkdir -p "$root"
    for f in "${pkgs[@]}"; do
        if command -v dpkg-deb >/dev/null; then
            dpkg-deb -x "$f" "$root"
        else
            tmp=$(mktemp -d)
            abs=$(realpath "$f")
            (cd "$tmp" && ar x "$abs")
            tar -xf "$tmp"/data.tar.* -C "$root"
            rm -rf "$tmp"
        fi
    done
    libs=$(find "$root" -name 'libvulkan.so.1' -printf '%h\n' | head -n1)
    [ -n "$libs" ] || die "the packages in $debs hold no libvulkan.so.1"
    export LD_LIBRARY_PATH="$libs${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
    say "Vulkan loader from $debs ($libs)"
fi
# A driver manifest outside the loader's search path (containers often mount NVIDIA's here).
if [ -z "${VK_DRIVER_FILES:-}${VK_ICD_FILENAMES:-}" ]; then
    for m in /usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json /usr/share/vulkan/icd.d/nvidia_icd.json /etc/vulkan/icd.d/nvidia_icd.json; do
        if [ -f "$m" ]; then
            export VK_DRIVER_FILES="$m"
            break
        fi
    done
fi

"$relief" adapters > "$out/adapters.txt" 2>"$out/adapters.err" || die "relief adapters failed: $(tail -n1 "$out/adapters.err")"
cat "$out/adapters.txt"
used=$(grep -m1 '^\*' "$out/adapters.txt" || true)
case "$used" in
    *"type Cpu"*) [ "${ALLOW_CPU:-}" = 1 ] || die "relief would use a software adapter ($used): no GPU found (ALLOW_CPU=1 runs anyway)" ;;
    "") die "relief sees no adapter" ;;
esac

status=0
sweep() { # name, out folder, extra args
    local grid=$1 dir=$2
    shift 2
    local t
    t=$(left)
    if [ "$t" -le 5 ]; then
        say "$grid: not started, the deadline has passed"
        status=1
        return
    fi
    say "$grid: up to $t s"
    local rc=0
    timeout --signal=INT --kill-after=10 "$t" "$relief" sweep --grid "$grid" --frames "$frames" --gpu-costs "$costs" --out "$dir" "$@" || rc=$?
    if [ $rc -eq 124 ] || [ $rc -eq 130 ] || [ $rc -eq 137 ]; then
        say "$grid: stopped at the deadline; its finished cells are kept (run again with the same OUT to resume)"
        status=1
    elif [ $rc -ne 0 ]; then
        say "$grid: relief sweep failed ($rc)"
        status=1
    fi
}

for t in $tables; do
    sweep "$t" "$out/tables"
done
sweep "$frontier" "$out/frontier" --size "$size"

for d in "$out/tables" "$out/frontier"; do
    if [ -f "$d/results.csv" ]; then
        "$relief" report "$d" >/dev/null || say "relief report $d failed"
    fi
done
{
    echo "elapsed_s=$(($(date +%s) - start)) deadline_s=$deadline frontier_size=$size"
    echo "adapter: $used"
    for d in "$out/tables" "$out/frontier"; do
        [ -f "$d/results.csv" ] && echo "$d: $(($(wc -l <"$d/results.csv") - 1)) rows"
    done
} | tee "$out/summary.txt"
exit $status
