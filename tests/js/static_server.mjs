// A static HTTP server on 127.0.0.1 and a free port, for the checks to read tilesets as a client would.
// `roots` maps URL prefixes to folders (the first that matches wins); requests outside a folder are refused.
import http from 'node:http';
import { readFile } from 'node:fs/promises';
import path from 'node:path';

const types = { '.html': 'text/html', '.js': 'text/javascript', '.mjs': 'text/javascript', '.json': 'application/json' };

export async function serveFolders(roots) {
  const resolved = roots.map(([prefix, folder]) => [prefix, path.resolve(folder)]);
  const server = http.createServer((req, res) => {
    const url = decodeURIComponent(new URL(req.url, 'http://localhost').pathname);
    const match = resolved.find(([prefix]) => url.startsWith(prefix));
    if (!match) return res.writeHead(404).end();
    const [prefix, root] = match;
    const file = path.join(root, url.slice(prefix.length) || 'index.html');
    if (file !== root && !file.startsWith(root + path.sep)) return res.writeHead(403).end();
    readFile(file).then(
      (body) => res.writeHead(200, { 'content-type': types[path.extname(file)] ?? 'application/octet-stream' }).end(body),
      () => res.writeHead(404).end(),
    );
  });
  await new Promise((resolve) => server.listen(0, '127.0.0.1', resolve));
  return { url: `http://127.0.0.1:${server.address().port}`, close: () => new Promise((r) => server.close(r)) };
}
