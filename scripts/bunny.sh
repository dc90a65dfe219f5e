#!/usr/bin/env bash
# Makes build/bunny.ply, the main job's default input: the Stanford bunny (decimated) from the npm package
# `bunny`, converted with node. Installs Debian's nodejs/npm only when npm is missing (an image that ships its
# own Node and npm conflicts with Debian's npm).
set -euo pipefail
cd "$(dirname "$0")/.."
out=build/bunny.ply
[[ -s $out ]] && exit 0
if ! command -v npm >/dev/null; then
  SUDO=""
  [[ $(id -u) -eq 0 ]] || SUDO="sudo"
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends nodejs npm >/dev/null
fi
mkdir -p build/npm
npm install --prefix build/npm --no-audit --no-fund --silent bunny@1.0.1 >/dev/null
node scripts/bunny_to_ply.js build/npm/node_modules/bunny "$out"
