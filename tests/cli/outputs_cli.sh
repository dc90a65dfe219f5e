#!/usr/bin/env bash
# Outputs never destroy: every verb given its own input as -o, a FIFO, /dev/null, a missing folder or a path
# under a file exits non-zero before any work and leaves the target as it was; a symbolic link is written
# through; --no-clobber keeps an existing file; a .jpg is JPEG; a name saying another format is refused; files
# and folders get the user's umask. No shared data needed: the inputs are made here.
set -euo pipefail
mv=$1
source "$(dirname "$0")/common.sh"
umask 022

write_tetra_ply "$dir/tetra.ply"
"$mv" build "$dir/tetra.ply" --resolution 32 -o "$dir/t.mvx" -q > /dev/null
"$mv" export "$dir/t.mvx" --format symvox-svdag -o "$dir/t.svdag" > /dev/null
{
  echo ply; echo "format ascii 1.0"; echo "element vertex 512"
  echo "property float x"; echo "property float y"; echo "property float z"; echo end_header
  for x in $(seq 0 7); do for y in $(seq 0 7); do for z in $(seq 0 7); do echo "$x $y.5 $z"; done; done; done
} > "$dir/cloud.ply"
"$mv" points build "$dir/cloud.ply" -o "$dir/c.mvx" -q > /dev/null
# A 24 x 16 grey PGM photograph and a model trained on it with itself as the mask's image.
{ printf 'P5\n24 16\n255\n'; head -c 384 /dev/zero | tr '\0' '\200'; } > "$dir/photo.pgm"
mkdir "$dir/train_img" "$dir/train_mask"
cp "$dir/photo.pgm" "$dir/train_img/p.pgm"
{ printf 'P5\n24 16\n255\n'; for i in $(seq 16); do head -c 12 /dev/zero; head -c 12 /dev/zero | tr '\0' '\377'; done; } \
  > "$dir/train_mask/p.pgm"
"$mv" mask train --images "$dir/train_img" --masks "$dir/train_mask" -o "$dir/m.mvm" > /dev/null

# What a path is: its type and inode, and a regular file's bytes (never read from a FIFO: that would block).
state() {
  stat -c '%F %i' "$1" 2>/dev/null || echo absent
  if [[ -f $1 && ! -L $1 ]]; then cksum < "$1"; fi
}

# refused WORDS TARGET ARGS...: a non-zero exit within a second, an error naming WORDS, TARGET unchanged.
refused() {
  local words=$1 target=$2; shift 2
  local before after start end
  before=$(state "$target")
  start=$(date +%s%N)
  if "$mv" "$@" > "$dir/out.txt" 2> "$dir/err.txt"; then fail "no error for: $*"; fi
  end=$(date +%s%N)
  grep -q "$words" "$dir/err.txt" || fail "'$*' said: $(cat "$dir/err.txt")"
  [[ $(wc -l < "$dir/err.txt") == 1 ]] || fail "'$*': more than one line: $(cat "$dir/err.txt")"
  after=$(state "$target")
  [[ $before == "$after" ]] || fail "'$*' changed $target"
  (( (end - start) / 1000000 < 1500 )) || fail "'$*' took $(( (end - start) / 1000000 )) ms to refuse"
}

# Each verb with its own input as the output (through a link to it, too).
ln -s t.mvx "$dir/link_to_t.mvx"
refused "is the input" "$dir/tetra.ply" build "$dir/tetra.ply" --resolution 32 -o "$dir/tetra.ply"
refused "is the input" "$dir/t.mvx" export "$dir/t.mvx" --format symvox-svdag -o "$dir/link_to_t.mvx"
refused "is the input" "$dir/t.svdag" import "$dir/t.svdag" -o "$dir/t.svdag"
refused "is the input" "$dir/t.mvx" render "$dir/t.mvx" -o "$dir/t.mvx"
refused "is the input" "$dir/cloud.ply" points build "$dir/cloud.ply" -o "$dir/cloud.ply"
refused "is the input" "$dir/c.mvx" points render "$dir/c.mvx" -o "$dir/c.mvx"
"$mv" render "$dir/t.mvx" -o "$dir/shot.png" --width 32 --height 24 --quiet
refused "is the input" "$dir/shot.png" mask apply "$dir/shot.png" --rect 2,2,10,10 -o "$dir"
refused "is the input" "$dir/train_mask/p.pgm" mask train --images "$dir/train_img" --masks "$dir/train_mask" \
  -o "$dir/train_mask/p.pgm"
ln "$dir/t.mvx" "$dir/hard.mvx"
refused "is the input" "$dir/t.mvx" export "$dir/hard.mvx" --format symvox-svdag -o "$dir/t.mvx"
mkdir "$dir/tiles_in"; cp "$dir/cloud.ply" "$dir/tiles_in/"
refused "holds the input" "$dir/tiles_in/cloud.ply" points build "$dir/tiles_in/cloud.ply" --format 3dtiles \
  -o "$dir/tiles_in"

# A FIFO, a device, a socket-like stream, a folder where a file is meant.
mkfifo "$dir/fifo.mvx"
refused "FIFO" "$dir/fifo.mvx" build "$dir/tetra.ply" --resolution 32 -o "$dir/fifo.mvx"
refused "FIFO" "$dir/fifo.mvx" render "$dir/t.mvx" -o "$dir/fifo.mvx"
refused "/dev" /dev/null build "$dir/tetra.ply" --resolution 32 -o /dev/null
refused "/dev" /dev/null points build "$dir/cloud.ply" -o /dev/null
refused "/dev\|/proc" /dev/null export "$dir/t.mvx" --format vdb -o /dev/stdout
[[ -c /dev/null && -L /dev/stdout ]] || fail "/dev/null or /dev/stdout changed"
mkdir "$dir/a_folder.mvx"
refused "folder" "$dir/a_folder.mvx" build "$dir/tetra.ply" --resolution 32 -o "$dir/a_folder.mvx"

# Missing folders and paths under a file fail before any work, even for a 16K^3 build.
refused "does not exist" "$dir/tetra.ply" build "$dir/tetra.ply" --resolution 16K -o "$dir/no/such/x.mvx"
refused "is a file" "$dir/tetra.ply" build "$dir/tetra.ply" --resolution 16K -o "$dir/tetra.ply/x.mvx"
refused "does not exist" "$dir/t.mvx" render "$dir/t.mvx" -o "$dir/no/x.png"
refused "is a file" "$dir/photo.pgm" mask apply "$dir/photo.pgm" --rect 2,2,10,10 -o "$dir/photo.pgm/masks"

# Names that say another format; --no-clobber.
refused "name it with .vdb" "$dir/t.mvx" export "$dir/t.mvx" --format vdb -o "$dir/t2.mvx"
refused "mvx" "$dir/t.mvx" render "$dir/t.mvx" -o "$dir/t3.mvx"
refused "no-clobber" "$dir/t.svdag" export "$dir/t.mvx" --format symvox-svdag -o "$dir/t.svdag" --no-clobber
[[ ! -e "$dir/t2.mvx" && ! -e "$dir/t3.mvx" ]] || fail "a refused output was written"

# A symbolic link is written through: the link stays, the file it names gets the bytes.
cp "$dir/t.mvx" "$dir/target.mvx"
ln -s target.mvx "$dir/link.mvx"
"$mv" build "$dir/tetra.ply" --resolution 16 -o "$dir/link.mvx" -q > /dev/null
[[ -L "$dir/link.mvx" ]] || fail "the link was replaced"
cmp -s "$dir/target.mvx" "$dir/t.mvx" && fail "the file the link names was not written"
"$mv" info "$dir/link.mvx" > /dev/null || fail "info through the link"

# JPEG for a .jpg name; PNG otherwise.
"$mv" render "$dir/t.mvx" -o "$dir/v.jpg" --width 64 --height 48 --quiet
[[ $(head -c 3 "$dir/v.jpg" | od -An -tx1 | tr -d ' ') == ffd8ff ]] || fail "v.jpg is not a JPEG"
"$mv" render "$dir/t.mvx" -o "$dir/v.png" --width 64 --height 48 --quiet
[[ $(head -c 4 "$dir/v.png" | od -An -tx1 | tr -d ' ') == 89504e47 ]] || fail "v.png is not a PNG"

# The umask: files 0644, folders 0755 (a tileset a web server running as another user can read).
"$mv" points build "$dir/cloud.ply" --format 3dtiles -o "$dir/tiles" -q > /dev/null
[[ $(stat -c %a "$dir/tiles") == 755 ]] || fail "tileset folder mode $(stat -c %a "$dir/tiles")"
[[ $(stat -c %a "$dir/tiles/tileset.json") == 644 ]] || fail "tileset.json mode $(stat -c %a "$dir/tiles/tileset.json")"
[[ $(stat -c %a "$dir/v.png") == 644 ]] || fail "v.png mode $(stat -c %a "$dir/v.png")"
(umask 027 && "$mv" render "$dir/t.mvx" -o "$dir/private.png" --width 8 --height 8 --quiet)
[[ $(stat -c %a "$dir/private.png") == 640 ]] || fail "umask 027 gave $(stat -c %a "$dir/private.png")"
chmod 600 "$dir/v.png"
"$mv" render "$dir/t.mvx" -o "$dir/v.png" --width 64 --height 48 --quiet
[[ $(stat -c %a "$dir/v.png") == 600 ]] || fail "a replaced file lost its permissions"

# Nothing temporary left behind by any of it.
left=$(find "$dir" -name '*.tmp*' -o -name '.*.tmp')
[[ -z $left ]] || fail "temporary files left: $left"
echo "outputs CLI: ok"
