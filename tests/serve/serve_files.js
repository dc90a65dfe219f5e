// Files of the serve session, made and read with node alone (no packages), sharing no code with megavox:
//   node serve_files.js png OUT          a 48 x 32 RGB PNG: a bright 16 x 12 box at (16, 10) on a dark ground
//   node serve_files.js grey PNG X,Y...  an 8-bit grey PNG's "WIDTHxHEIGHT" and its values at the points
//   node serve_files.js 3tz FILE         checks a 3D Tiles archive; prints its entries' names
"use strict";
const fs = require("fs");
const zlib = require("zlib");
const crypto = require("crypto");

function crc32(bytes) {
  let c = ~0;
  for (const b of bytes) {
    c ^= b;
    for (let k = 0; k < 8; k++) c = c & 1 ? (c >>> 1) ^ 0xedb88320 : c >>> 1;
  }
  return ~c >>> 0;
}

function chunk(type, data) {
  const len = Buffer.alloc(4);
  len.writeUInt32BE(data.length);
  const body = Buffer.concat([Buffer.from(type, "ascii"), data]);
  const crc = Buffer.alloc(4);
  crc.writeUInt32BE(crc32(body));
  return Buffer.concat([len, body, crc]);
}

function writePng(out) {
  const w = 48, h = 32;
  const rows = [];
  for (let y = 0; y < h; y++) {
    const row = Buffer.alloc(1 + 3 * w);  // filter 0
    for (let x = 0; x < w; x++) {
      const inside = x >= 16 && x < 32 && y >= 10 && y < 22;
      row.set(inside ? [230, 200, 40] : [20 + ((x * 7 + y * 3) % 11), 30, 60], 1 + 3 * x);
    }
    rows.push(row);
  }
  const ihdr = Buffer.alloc(13);
  ihdr.writeUInt32BE(w, 0);
  ihdr.writeUInt32BE(h, 4);
  ihdr.set([8, 2, 0, 0, 0], 8);  // 8-bit RGB
  fs.writeFileSync(out, Buffer.concat([Buffer.from([137, 80, 78, 71, 13, 10, 26, 10]), chunk("IHDR", ihdr),
                                       chunk("IDAT", zlib.deflateSync(Buffer.concat(rows))), chunk("IEND", Buffer.alloc(0))]));
}

// Reads an 8-bit grey PNG (filters 0-4) and prints its size and the values at the points.
function readGrey(file, points) {
  const b = fs.readFileSync(file);
  if (b.toString("latin1", 1, 4) !== "PNG") throw new Error("not a PNG");
  let off = 8, w = 0, h = 0, idat = [];
  while (off < b.length) {
    const len = b.readUInt32BE(off), type = b.toString("ascii", off + 4, off + 8), data = b.subarray(off + 8, off + 8 + len);
    if (type === "IHDR") {
      w = data.readUInt32BE(0);
      h = data.readUInt32BE(4);
      if (data[8] !== 8 || data[9] !== 0) throw new Error(`not 8-bit grey: depth ${data[8]}, colour type ${data[9]}`);
    }
    if (type === "IDAT") idat.push(data);
    off += 12 + len;
  }
  const raw = zlib.inflateSync(Buffer.concat(idat));
  const px = Buffer.alloc(w * h);
  for (let y = 0; y < h; y++) {
    const f = raw[y * (w + 1)];
    for (let x = 0; x < w; x++) {
      const v = raw[y * (w + 1) + 1 + x];
      const a = x ? px[y * w + x - 1] : 0, up = y ? px[(y - 1) * w + x] : 0, c = x && y ? px[(y - 1) * w + x - 1] : 0;
      const p = a + up - c, pa = Math.abs(p - a), pb = Math.abs(p - up), pc = Math.abs(p - c);
      const pred = [0, a, up, (a + up) >> 1, pa <= pb && pa <= pc ? a : pb <= pc ? up : c][f];
      px[y * w + x] = (v + pred) & 255;
    }
  }
  const values = points.map((p) => { const [x, y] = p.split(",").map(Number); return px[y * w + x]; });
  console.log(`${w}x${h} ${values.join(" ")}`);
}

// The 3D Tiles archive rules: stored entries with their CRC and sizes in the local headers, tileset.json
// first, @3dtilesIndex1@ last, and the index holding every other entry's path MD5 and local header offset,
// sorted by the MD5 read as two little-endian u64.
function check3tz(file) {
  const b = fs.readFileSync(file);
  const eocd = b.lastIndexOf(Buffer.from([0x50, 0x4b, 0x05, 0x06]));
  if (eocd < 0) throw new Error("no end of central directory");
  const count = b.readUInt16LE(eocd + 10);
  let off = b.readUInt32LE(eocd + 16);
  const entries = [];
  for (let i = 0; i < count; i++) {
    if (b.readUInt32LE(off) !== 0x02014b50) throw new Error(`central entry ${i}: bad signature`);
    const e = { method: b.readUInt16LE(off + 10), crc: b.readUInt32LE(off + 16), csize: b.readUInt32LE(off + 20),
                size: b.readUInt32LE(off + 24), local: b.readUInt32LE(off + 42) };
    const n = b.readUInt16LE(off + 28), x = b.readUInt16LE(off + 30), c = b.readUInt16LE(off + 32);
    e.name = b.toString("utf8", off + 46, off + 46 + n);
    off += 46 + n + x + c;
    const l = e.local;
    if (b.readUInt32LE(l) !== 0x04034b50) throw new Error(`${e.name}: no local header at ${l}`);
    if (e.method !== 0) throw new Error(`${e.name}: compressed (method ${e.method})`);
    if (b.readUInt16LE(l + 6) & 8 || b.readUInt32LE(l + 14) !== e.crc || b.readUInt32LE(l + 18) !== e.csize ||
        b.readUInt32LE(l + 22) !== e.size)
      throw new Error(`${e.name}: the local header lacks its CRC or sizes`);
    const ln = b.readUInt16LE(l + 26), lx = b.readUInt16LE(l + 28);
    e.data = b.subarray(l + 30 + ln + lx, l + 30 + ln + lx + e.size);
    if (crc32(e.data) !== e.crc) throw new Error(`${e.name}: CRC mismatch`);
    entries.push(e);
  }
  if (entries[0].name !== "tileset.json") throw new Error(`first entry ${entries[0].name}`);
  const index = entries[entries.length - 1];
  if (index.name !== "@3dtilesIndex1@") throw new Error(`last entry ${index.name}`);
  if (index.size !== 24 * (entries.length - 1)) throw new Error(`index of ${index.size} bytes for ${entries.length - 1} files`);
  const key = (h) => [h.readBigUInt64LE(0), h.readBigUInt64LE(8)];
  let last = null;
  const seen = new Set();
  for (let i = 0; i < index.size; i += 24) {
    const h = index.data.subarray(i, i + 16), at = Number(index.data.readBigUInt64LE(i + 16));
    const k = key(h);
    if (last && (k[0] < last[0] || (k[0] === last[0] && k[1] < last[1]))) throw new Error("index not sorted");
    last = k;
    const e = entries.find((x) => x.local === at);
    if (!e) throw new Error(`index offset ${at} is no entry`);
    if (!crypto.createHash("md5").update(e.name).digest().equals(h)) throw new Error(`index hash of ${e.name}`);
    seen.add(e.name);
  }
  if (seen.size !== entries.length - 1) throw new Error("the index misses entries");
  JSON.parse(entries[0].data.toString("utf8"));
  for (const e of entries) console.log(e.name);
}

const [cmd, file, ...rest] = process.argv.slice(2);
try {
  if (cmd === "png") writePng(file);
  else if (cmd === "grey") readGrey(file, rest);
  else if (cmd === "3tz") check3tz(file);
  else throw new Error(`unknown command ${cmd}`);
} catch (e) {
  console.error(`${file}: ${e.message}`);
  process.exit(1);
}
