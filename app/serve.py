"""The dashboard served from a script (the browser tests, the benchmarks): warmed up, on a free port."""

from __future__ import annotations

import os
import socket
import subprocess
import sys
import time
import urllib.request
from pathlib import Path

__all__ = ["TEXT_JS", "free_port", "serve"]

ROOT = Path(__file__).resolve().parents[1]
#: the page's text, shadow DOM included (Bokeh and Panel render into shadow roots)
TEXT_JS = """
() => {
  const out = [];
  function walk(node) {
    if (node.shadowRoot) walk(node.shadowRoot);
    for (const c of node.childNodes) {
      if (c.nodeType === Node.TEXT_NODE) out.push(c.textContent);
      else if (c.nodeType === Node.ELEMENT_NODE && c.tagName !== "SCRIPT" && c.tagName !== "STYLE") walk(c);
    }
  }
  walk(document.body);
  return out.join(" ");
}
"""


def free_port() -> int:
    """A TCP port of 127.0.0.1 free at the time of the call."""
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def serve(
    log_path: Path, args: tuple[str, ...] = (), env: dict[str, str] | None = None, timeout: float = 900.0
) -> tuple[subprocess.Popen, str]:
    """``panel serve app/app.py --setup app/warmup.py`` on 127.0.0.1 and a free port, logging to
    ``log_path``; the server process and the app's address once it answers.

    ``args``: the app's own arguments (``--args ...``, e.g. ``--study RESULT.zarr``); ``env``: the
    server's environment (default this one), with the repository first on ``PYTHONPATH``. Raises
    ``RuntimeError`` with the log when the server stops or does not answer within ``timeout`` seconds
    (a fresh install compiles every kernel before the server starts).
    """
    port = free_port()
    env = dict(os.environ if env is None else env)
    env["PYTHONPATH"] = os.pathsep.join(filter(None, [str(ROOT), env.get("PYTHONPATH")]))
    command = [sys.executable, "-m", "panel", "serve", "app/app.py", "--address", "127.0.0.1",
               "--port", str(port), "--allow-websocket-origin", f"127.0.0.1:{port}",
               "--setup", "app/warmup.py", *(["--args", *args] if args else [])]  # fmt: skip
    with open(log_path, "w") as log:
        proc = subprocess.Popen(command, cwd=ROOT, env=env, stdout=log, stderr=subprocess.STDOUT)
    url, deadline = f"http://127.0.0.1:{port}/app", time.monotonic() + timeout
    while True:
        try:
            with urllib.request.urlopen(url, timeout=60) as response:
                if response.status == 200:
                    return proc, url
        except OSError:
            if proc.poll() is not None or time.monotonic() > deadline:
                proc.kill()
                raise RuntimeError(f"the server did not start:\n{Path(log_path).read_text()}") from None
            time.sleep(0.5)
