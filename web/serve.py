#!/usr/bin/env python3
"""Serves build/web on 127.0.0.1 (scripts/web.sh serve [--port N]): a static server that names
.wasm and .js files with the types browsers want (application/wasm for streaming compilation)
and sends the cross-origin isolation headers (Cross-Origin-Opener-Policy: same-origin,
Cross-Origin-Embedder-Policy: require-corp), without which a browser gives a page no
SharedArrayBuffer: the page then runs the threaded module (maille-mt.js, Web Workers). Any other
static server works too; without those headers the page runs on one thread (docs/web.md).
--no-isolation leaves the headers out (to see the one-thread page)."""
import argparse
import functools
import http.server
import sys

parser = argparse.ArgumentParser()
parser.add_argument("--port", type=int, default=8000)
parser.add_argument("--dir", default="build/web")
parser.add_argument("--no-isolation", action="store_true",
                    help="no COOP/COEP headers: the page runs on one thread")
args = parser.parse_args()


class Handler(http.server.SimpleHTTPRequestHandler):
    extensions_map = {**http.server.SimpleHTTPRequestHandler.extensions_map,
                      ".wasm": "application/wasm", ".js": "text/javascript",
                      ".mjs": "text/javascript", ".toml": "text/plain"}

    def end_headers(self):
        if not args.no_isolation:
            self.send_header("Cross-Origin-Opener-Policy", "same-origin")
            self.send_header("Cross-Origin-Embedder-Policy", "require-corp")
        super().end_headers()


try:
    server = http.server.ThreadingHTTPServer(
        ("127.0.0.1", args.port), functools.partial(Handler, directory=args.dir))
except OSError as e:
    sys.exit(f"web.sh serve: cannot listen on 127.0.0.1:{args.port}: {e.strerror}")
mode = "one thread (no isolation headers)" if args.no_isolation else "cross-origin isolated: threads"
print(f"Maille in the browser: http://127.0.0.1:{args.port}/ ({mode}; Ctrl+C stops)", flush=True)
try:
    server.serve_forever()
except KeyboardInterrupt:
    pass
