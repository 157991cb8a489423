// A static file server for the Lottie player tests: `node serve.mjs ROOT [WORK]` serves the
// folder ROOT, and WORK under /work/, on 127.0.0.1 at a free port, which it prints as its first
// line. Module scripts and WebAssembly need http (browsers refuse them from file:// pages).
// Only files under those folders are served.
import { createServer } from "node:http";
import { readFile } from "node:fs/promises";
import { resolve, extname, sep } from "node:path";

const root = resolve(process.argv[2] ?? ".");
const work = process.argv[3] ? resolve(process.argv[3]) : null;
const types = {
  ".html": "text/html; charset=utf-8",
  ".js": "text/javascript",
  ".mjs": "text/javascript",
  ".json": "application/json",
  ".wasm": "application/wasm",
  ".lottie": "application/zip",
  ".png": "image/png",
};

const server = createServer(async (req, res) => {
  let url = decodeURIComponent(new URL(req.url, "http://x").pathname);
  let base = root;
  if (work && url.startsWith("/work/")) {
    base = work;
    url = url.slice("/work".length);
  }
  const path = resolve(base, "." + url);
  if (path !== base && !path.startsWith(base + sep)) {
    res.writeHead(403).end();
    return;
  }
  try {
    const body = await readFile(path);
    res.writeHead(200, { "content-type": types[extname(path)] ?? "application/octet-stream" });
    res.end(body);
  } catch {
    res.writeHead(404).end();
  }
});
server.listen(0, "127.0.0.1", () => {
  console.log(server.address().port);
});
