// Headless-Chromium driver for relief's browser tests.
//
// Serves a folder over http://127.0.0.1 (a random free port), opens one page in Debian's
// Chromium with SwiftShader's WebGPU and WebGL2, collects console messages and page errors,
// waits until the page sets `window.__done = true`, and prints one JSON object on stdout:
//
//   { "ok": bool, "result": window.__result, "console": [{type, text}], "errors": [text],
//     "timed_out": bool, "screenshot": path|null }
//
// `ok` is false when the page threw, logged a console error, timed out, or set
// `window.__result.ok === false`. The exit code is 0 when ok, 1 otherwise, 2 on bad usage.
//
// Usage:
//   node run.mjs --page PATH [--root DIR] [--mount /PREFIX=DIR]... [--query K=V]...
//                [--timeout-ms N] [--screenshot FILE] [--size WxH] [--chromium PATH]
//
// --root DIR       the folder served at / (default: this folder, so that pages import
//                  /node_modules/three/...);
// --page PATH      the page's path under the server (e.g. /pages/caps.html);
// --mount P=DIR    serve DIR under /P/ too (generated shaders, pictures);
// --query K=V      appended to the page's URL as a query parameter;
// --timeout-ms N   how long to wait for window.__done (default 60000);
// --screenshot F   a PNG of the page once done;
// --size WxH       the viewport (default 512x512).

import http from 'node:http';
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { fileURLToPath } from 'node:url';
import puppeteer from 'puppeteer-core';

const here = path.dirname(fileURLToPath(import.meta.url));

/** The flags that give headless Chromium WebGPU and WebGL2 on SwiftShader, offline. */
export const CHROMIUM_FLAGS = [
  '--no-sandbox',
  '--enable-unsafe-webgpu',
  '--enable-features=Vulkan',
  '--use-vulkan=swiftshader',
  '--use-webgpu-adapter=swiftshader',
  '--use-angle=swiftshader',
  '--enable-unsafe-swiftshader',
  '--disable-background-networking',
  '--disable-component-update',
  '--disable-sync',
  '--no-first-run',
];

function parseArgs(argv) {
  const a = { root: here, page: null, mounts: [], query: [], timeoutMs: 60000, screenshot: null, size: [512, 512], chromium: '/usr/bin/chromium' };
  for (let i = 0; i < argv.length; i++) {
    const k = argv[i];
    const v = () => {
      if (i + 1 >= argv.length) throw new Error(`${k} needs a value`);
      return argv[++i];
    };
    if (k === '--root') a.root = path.resolve(v());
    else if (k === '--page') a.page = v();
    else if (k === '--mount') {
      const m = v();
      const eq = m.indexOf('=');
      if (eq < 1) throw new Error(`--mount takes /PREFIX=DIR, not \`${m}\``);
      a.mounts.push([m.slice(0, eq).replace(/^\/+|\/+$/g, ''), path.resolve(m.slice(eq + 1))]);
    } else if (k === '--query') a.query.push(v());
    else if (k === '--timeout-ms') a.timeoutMs = Number(v());
    else if (k === '--screenshot') a.screenshot = path.resolve(v());
    else if (k === '--size') {
      const [w, h] = v().split('x').map(Number);
      if (!(w > 0 && h > 0)) throw new Error('--size takes WxH');
      a.size = [w, h];
    } else if (k === '--chromium') a.chromium = v();
    else throw new Error(`unknown argument \`${k}\``);
  }
  if (!a.page) throw new Error('--page PATH is required');
  if (!(a.timeoutMs > 0)) throw new Error('--timeout-ms takes a positive number');
  return a;
}

const TYPES = {
  '.html': 'text/html', '.js': 'text/javascript', '.mjs': 'text/javascript', '.json': 'application/json',
  '.wgsl': 'text/plain', '.glsl': 'text/plain', '.png': 'image/png', '.bin': 'application/octet-stream',
  '.css': 'text/css', '.txt': 'text/plain', '.map': 'application/json',
};

/** A static file server on 127.0.0.1 over `root` and the mounts; resolves to [server, port]. */
function serve(root, mounts) {
  const server = http.createServer((req, res) => {
    const url = new URL(req.url, 'http://127.0.0.1');
    if (url.pathname === '/favicon.ico') {
      res.writeHead(204).end();
      return;
    }
    let rel = decodeURIComponent(url.pathname).replace(/^\/+/, '');
    let base = root;
    for (const [prefix, dir] of mounts) {
      if (rel === prefix || rel.startsWith(prefix + '/')) {
        base = dir;
        rel = rel.slice(prefix.length).replace(/^\/+/, '');
        break;
      }
    }
    const file = path.resolve(base, rel);
    if (!file.startsWith(path.resolve(base))) {
      res.writeHead(403).end();
      return;
    }
    fs.readFile(file, (err, data) => {
      if (err) {
        res.writeHead(404, { 'content-type': 'text/plain' }).end(`not found: ${url.pathname}`);
        return;
      }
      res.writeHead(200, { 'content-type': TYPES[path.extname(file)] ?? 'application/octet-stream', 'cache-control': 'no-store' });
      res.end(data);
    });
  });
  return new Promise((resolve, reject) => {
    server.on('error', reject);
    server.listen(0, '127.0.0.1', () => resolve([server, server.address().port]));
  });
}

async function main() {
  let args;
  try {
    args = parseArgs(process.argv.slice(2));
  } catch (e) {
    process.stderr.write(`run.mjs: ${e.message}\n`);
    process.exit(2);
  }
  const out = { ok: false, result: null, console: [], errors: [], timed_out: false, screenshot: null };
  const userDataDir = fs.mkdtempSync(path.join(os.tmpdir(), 'relief-chromium-'));
  const [server, port] = await serve(args.root, args.mounts);
  let browser;
  try {
    browser = await puppeteer.launch({
      executablePath: args.chromium,
      headless: true,
      userDataDir,
      args: [...CHROMIUM_FLAGS, `--window-size=${args.size[0]},${args.size[1]}`],
      defaultViewport: { width: args.size[0], height: args.size[1], deviceScaleFactor: 1 },
      protocolTimeout: args.timeoutMs + 30000,
    });
    const page = await browser.newPage();
    page.on('console', (m) => out.console.push({ type: m.type(), text: m.text() }));
    page.on('pageerror', (e) => out.errors.push(String(e && e.stack ? e.stack : e)));
    page.on('requestfailed', (r) => out.errors.push(`request failed: ${r.url()} (${r.failure()?.errorText})`));
    page.on('response', (r) => {
      if (r.status() >= 400) out.errors.push(`HTTP ${r.status()}: ${r.url()}`);
    });
    const qs = args.query.length ? '?' + args.query.map((q) => {
      const eq = q.indexOf('=');
      return eq < 0 ? encodeURIComponent(q) : `${encodeURIComponent(q.slice(0, eq))}=${encodeURIComponent(q.slice(eq + 1))}`;
    }).join('&') : '';
    const url = `http://127.0.0.1:${port}/${args.page.replace(/^\/+/, '')}${qs}`;
    await page.goto(url, { waitUntil: 'load', timeout: args.timeoutMs });
    try {
      await page.waitForFunction('window.__done === true', { timeout: args.timeoutMs, polling: 100 });
    } catch (e) {
      out.timed_out = true;
      out.errors.push(`the page did not set window.__done within ${args.timeoutMs} ms`);
    }
    out.result = await page.evaluate(() => window.__result ?? null);
    if (args.screenshot) {
      await page.screenshot({ path: args.screenshot });
      out.screenshot = args.screenshot;
    }
  } catch (e) {
    out.errors.push(`driver: ${e && e.stack ? e.stack : e}`);
  } finally {
    if (browser) await browser.close().catch(() => {});
    server.close();
    fs.rmSync(userDataDir, { recursive: true, force: true });
  }
  const consoleErrors = out.console.filter((m) => m.type === 'error');
  out.ok = !out.timed_out && out.errors.length === 0 && consoleErrors.length === 0 && !(out.result && out.result.ok === false);
  // Exit once the whole report is written: a pipe takes 64 KiB at a time, and an exit
  // before it drains would cut a large result short.
  process.stdout.write(JSON.stringify(out) + '\n', () => process.exit(out.ok ? 0 : 1));
}

main();
