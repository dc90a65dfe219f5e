// An independent LAZ decoder that megavox's own LAZ reader is checked against: laz-perf (LASzip compiled to
// WebAssembly, not megavox code) decodes every point of a LAZ file, and the decoded point records are written
// back to back, in file order, as the reader hands them out (point_length bytes each, no header). Tests compare
// megavox's decoded records with these; benchmarks use the decode time as a reference.
// Prints one JSON line: {"points":N,"point_length":L,"point_format":F,"seconds":S}, where seconds is the
// decode time only (opening the file in laz-perf and decoding all points; not node start-up, WebAssembly
// instantiation, reading the file or writing the output), the best of the repeats.
// Exits 1 on any problem with the file, 2 on bad arguments.
//   node laz_decode.mjs [--repeats R] IN.laz OUT.bin
//   node laz_decode.mjs [--repeats R] --no-output IN.laz [OUT.bin]   (decodes, writes nothing)
// laz-perf keeps the whole file in its WebAssembly memory (2 GiB at most) and counts points in 32 bits; it
// reads LASzip item version 2 and 3 files (also COPC, as one file), and passes an uncompressed LAS file's
// records through as they are.
import { closeSync, openSync, readFileSync, unlinkSync, writeSync } from 'node:fs';
import { performance } from 'node:perf_hooks';
import { createLazPerf } from 'laz-perf';

const usage = 'usage: node laz_decode.mjs [--repeats R] [--no-output] IN.laz [OUT.bin]';
let repeats = 1;
let writeOutput = true;
const positional = [];
const args = process.argv.slice(2);
for (let i = 0; i < args.length; i++) {
  if (args[i] === '--no-output') writeOutput = false;
  else if (args[i] === '--repeats') {
    if (!/^[1-9]\d*$/.test(args[i + 1] ?? '')) {
      console.error(`laz_decode: --repeats needs a positive integer\n${usage}`);
      process.exit(2);
    }
    repeats = Number(args[++i]);
  } else if (args[i].startsWith('--')) {
    console.error(`laz_decode: unknown option ${args[i]}\n${usage}`);
    process.exit(2);
  } else positional.push(args[i]);
}
const [inPath, outPath] = positional;
if (!inPath || positional.length > 2 || (writeOutput && !outPath)) {
  console.error(usage);
  process.exit(2);
}

// Points are decoded into a batch of this many bytes in laz-perf's memory, then copied out to the output.
const BATCH_BYTES = 4 << 20;

let L; // the laz-perf module
// laz-perf is built without C++ exception support: a C++ throw reaches JS as the string
// "<pointer> - Exception catching is disabled, ...". Its exceptions are std::runtime_error (libc++, wasm32:
// the message pointer follows the vtable pointer), so the message can usually be read back from the heap.
function describe(e) {
  const m = typeof e === 'string' ? /^(\d+) - Exception catching is disabled/.exec(e) : null;
  if (!m || !L) return e instanceof Error ? e.message : String(e);
  try {
    const heap = L.HEAPU8;
    const at = new DataView(heap.buffer).getUint32(Number(m[1]) + 4, true);
    const end = heap.indexOf(0, at);
    const text = end > at && end - at < 1000 ? Buffer.from(heap.subarray(at, end)).toString('latin1') : '';
    if (/^[\x20-\x7e]+$/.test(text)) return `laz-perf: ${text}`;
  } catch {
    // fall through to the generic message
  }
  return 'laz-perf threw a C++ exception (its message could not be read)';
}

let filePtr = 0;
let batchPtr = 0;
let fd = -1;
try {
  let bytes;
  try {
    bytes = readFileSync(inPath);
  } catch (e) {
    throw new Error(`cannot read: ${e.message}`);
  }
  L = await createLazPerf();
  filePtr = L._malloc(bytes.byteLength);
  if (!filePtr) throw new Error(`${bytes.byteLength} bytes do not fit in laz-perf's memory`);
  L.HEAPU8.set(bytes, filePtr);

  let best = Infinity;
  let info;
  for (let r = 0; r < repeats; r++) {
    const output = writeOutput && r === 0;
    const zip = new L.LASZip();
    try {
      let seconds = 0;
      let t = performance.now();
      zip.open(filePtr, bytes.byteLength);
      const points = zip.getCount();
      const pointLength = zip.getPointLength();
      const pointFormat = zip.getPointFormat();
      seconds += performance.now() - t;
      if (!(pointLength > 0)) throw new Error(`point record length ${pointLength}`);
      info = { points, point_length: pointLength, point_format: pointFormat };
      const batchPoints = Math.max(1, Math.floor(BATCH_BYTES / pointLength));
      if (!batchPtr) {
        batchPtr = L._malloc(batchPoints * pointLength);
        if (!batchPtr) throw new Error('no memory for the decode batch');
      }
      if (output) fd = openSync(outPath, 'w');
      for (let done = 0; done < points; ) {
        const n = Math.min(batchPoints, points - done);
        t = performance.now();
        for (let i = 0, p = batchPtr; i < n; i++, p += pointLength) zip.getPoint(p);
        seconds += performance.now() - t;
        if (output) writeSync(fd, L.HEAPU8.subarray(batchPtr, batchPtr + n * pointLength));
        done += n;
      }
      if (output) {
        closeSync(fd);
        fd = -1;
      }
      best = Math.min(best, seconds / 1000);
    } finally {
      try {
        zip.delete();
      } catch {
        // after a C++ throw laz-perf's state is not to be trusted; the first error is the one to report
      }
    }
  }
  console.log(JSON.stringify({ ...info, seconds: Number(best.toFixed(6)) }));
} catch (e) {
  console.error(`laz_decode: ${inPath}: ${describe(e)}`);
  if (fd >= 0) {
    closeSync(fd);
    try {
      unlinkSync(outPath); // no partial output for a test to read
    } catch {
      // nothing to remove
    }
  }
  process.exit(1);
} finally {
  if (L && batchPtr) L._free(batchPtr);
  if (L && filePtr) L._free(filePtr);
}
