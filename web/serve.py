#!/usr/bin/env python3
"""Serves build/web on 127.0.0.1 (scripts/web.sh serve [--port N]): a plain static server that
names .wasm and .js files with the types browsers want (application/wasm for streaming
compilation). The page needs nothing else: it runs on one thread, so no cross-origin isolation
headers are needed."""
import argparse
import functools
import http.server
import sys

parser = argparse.ArgumentParser()
parser.add_argument("--port", type=int, default=8000)
parser.add_argument("--dir", default="build/web")
args = parser.parse_args()

Handler = functools.partial(http.server.SimpleHTTPRequestHandler, directory=args.dir)
Handler.func.extensions_map = {**http.server.SimpleHTTPRequestHandler.extensions_map,
                               ".wasm": "application/wasm", ".js": "text/javascript",
                               ".mjs": "text/javascript", ".toml": "text/plain"}
try:
    server = http.server.ThreadingHTTPServer(("127.0.0.1", args.port), Handler)
except OSError as e:
    sys.exit(f"web.sh serve: cannot listen on 127.0.0.1:{args.port}: {e.strerror}")
print(f"Maille in the browser: http://127.0.0.1:{args.port}/ (Ctrl+C stops)", flush=True)
try:
    server.serve_forever()
except KeyboardInterrupt:
    pass
