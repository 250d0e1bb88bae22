#!/usr/bin/env bash
# Downloads the Vulkan loader as Debian packages (amd64) into .gl/ (or $1), for
# docs/notes/gpu/run.sh on a GPU machine that has no loader and no network. Run once, from the
# repository root, on any Debian or Ubuntu machine with apt; nothing is installed. The
# packages are Debian's for this machine's release; the loader needs only the C library.
set -euo pipefail
dir=${1:-.gl}
lists=$(mktemp -d)
mkdir -p "$dir" "$lists/partial"
o=(-oAPT::Architecture=amd64 -oAPT::Architectures=amd64 "-oDir::State::Lists=$lists")
apt-get "${o[@]}" update -qq
(cd "$dir" && apt-get "${o[@]}" download libvulkan1)
rm -rf "$lists"
ls -l "$dir"
