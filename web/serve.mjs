// A static server for web/ that sends the app compressed: the wasm is about 11 MB as built and
// under 4 MB compressed, so a server that sends it raw (`python3 -m http.server`) makes the app
// start several seconds later on a school's network. No npm packages: Node alone runs it.
//
//   node web/serve.mjs [--port 8000] [--host 127.0.0.1]    then open http://127.0.0.1:8000/
//
// A file is sent brotli- or gzip-compressed when the browser accepts it: from the `.br` or
// `.gz` file beside it when `scripts/build-web` wrote one newer than the file, else compressed
// once here and kept in memory until the file changes. Any server that does the same serves
// accelviz as well (nginx's `gzip_static`/`brotli_static`, Caddy's `precompressed`).

import http from 'node:http';
import fs from 'node:fs';
import path from 'node:path';
import zlib from 'node:zlib';
import { fileURLToPath } from 'node:url';

const TYPES = {
  '.html': 'text/html; charset=utf-8',
  '.js': 'text/javascript',
  '.mjs': 'text/javascript',
  '.wasm': 'application/wasm',
  '.json': 'application/json',
  '.obj': 'text/plain',
};

/** Files worth compressing (text and wasm; images and archives are compressed already). */
const COMPRESSIBLE = new Set(['.html', '.js', '.mjs', '.wasm', '.json', '.obj']);

/** The encodings this server sends, best first, by their `.ext` and compressor. */
const ENCODINGS = [
  {
    name: 'br',
    ext: '.br',
    compress: (bytes) => zlib.brotliCompressSync(bytes, {
      params: { [zlib.constants.BROTLI_PARAM_QUALITY]: 9, [zlib.constants.BROTLI_PARAM_SIZE_HINT]: bytes.length },
    }),
  },
  { name: 'gzip', ext: '.gz', compress: (bytes) => zlib.gzipSync(bytes, { level: 9 }) },
];

/** Whether `accept` (an Accept-Encoding header) takes `encoding` (q=0 refuses it). */
export function accepts(accept, encoding) {
  return (accept ?? '').split(',').some((part) => {
    const [name, ...params] = part.trim().split(';');
    const q = params.map((p) => p.trim()).find((p) => p.startsWith('q='));
    return name.trim().toLowerCase() === encoding && !(q && Number(q.slice(2)) === 0);
  });
}

/**
 * Serves `dir` on `port` (0: a free one) at `host`; resolves to the listening server.
 * `log` hears one line a request.
 */
export function serve(dir, { port = 0, host = '127.0.0.1', log = () => {} } = {}) {
  const root = path.resolve(dir);
  const compressed = new Map(); // `${file}${ext}` -> { mtimeMs, bytes }

  function body(file, stat, encoding) {
    const beside = file + encoding.ext;
    if (fs.existsSync(beside) && fs.statSync(beside).mtimeMs >= stat.mtimeMs) {
      return fs.readFileSync(beside);
    }
    const key = file + encoding.ext;
    const kept = compressed.get(key);
    if (kept && kept.mtimeMs === stat.mtimeMs) return kept.bytes;
    const bytes = encoding.compress(fs.readFileSync(file));
    compressed.set(key, { mtimeMs: stat.mtimeMs, bytes });
    return bytes;
  }

  const server = http.createServer((request, response) => {
    let urlPath;
    try {
      urlPath = decodeURIComponent(new URL(request.url, 'http://x').pathname);
    } catch {
      response.writeHead(400).end('bad request');
      return;
    }
    const file = path.join(root, urlPath.endsWith('/') ? path.join(urlPath, 'index.html') : urlPath);
    if (!file.startsWith(root) || !fs.existsSync(file) || fs.statSync(file).isDirectory()) {
      response.writeHead(404).end('not found');
      log(`404 ${urlPath}`);
      return;
    }
    const stat = fs.statSync(file);
    const extension = path.extname(file);
    const headers = {
      'content-type': TYPES[extension] ?? 'application/octet-stream',
      'cache-control': 'no-cache',
      vary: 'accept-encoding',
    };
    const encoding = COMPRESSIBLE.has(extension)
      ? ENCODINGS.find((e) => accepts(request.headers['accept-encoding'], e.name))
      : undefined;
    let bytes;
    if (encoding) {
      bytes = body(file, stat, encoding);
      headers['content-encoding'] = encoding.name;
      // What the page's progress bar counts: the bytes it will hold once decoded.
      headers['x-decoded-length'] = String(stat.size);
    } else {
      bytes = fs.readFileSync(file);
    }
    headers['content-length'] = bytes.length;
    response.writeHead(200, headers);
    response.end(request.method === 'HEAD' ? undefined : bytes);
    log(`200 ${urlPath} ${encoding ? `${encoding.name} ` : ''}${bytes.length} bytes`);
  });
  return new Promise((resolve, reject) => {
    server.once('error', reject);
    server.listen(port, host, () => resolve(server));
  });
}

if (process.argv[1] && path.resolve(process.argv[1]) === fileURLToPath(import.meta.url)) {
  const options = { port: 8000, host: '127.0.0.1' };
  const args = process.argv.slice(2);
  for (let i = 0; i < args.length; i += 2) {
    const name = args[i].replace(/^--/, '');
    if (!(name in options) || args[i + 1] === undefined) {
      console.error(`serve.mjs: unknown or incomplete option '${args[i]}'; options: --port N --host ADDRESS`);
      process.exit(2);
    }
    options[name] = name === 'port' ? Number(args[i + 1]) : args[i + 1];
  }
  const dir = path.dirname(fileURLToPath(import.meta.url));
  if (!fs.existsSync(path.join(dir, 'pkg', 'accelviz_bg.wasm'))) {
    console.error('serve.mjs: web/pkg/accelviz_bg.wasm is missing: run scripts/build-web first');
    process.exit(2);
  }
  serve(dir, { ...options, log: (line) => console.log(line) }).then(
    (server) => console.log(`serving ${dir} compressed at http://${options.host}:${server.address().port}/`),
    (error) => {
      console.error(`serve.mjs: cannot listen on ${options.host}:${options.port}: ${error.message}`);
      process.exit(2);
    },
  );
}
