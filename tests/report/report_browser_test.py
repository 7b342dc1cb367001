#!/usr/bin/env python3
"""A report's index.html in a real headless browser (Debian's chromium, docs/report.md): the page loads without
console errors, exceptions or failed requests, every <img> decodes (naturalWidth > 0), and a screenshot is taken
(WORK_DIR/screenshot.png). Talks to chromium over the DevTools protocol (a WebSocket, implemented here with the
standard library). Exit 77 (ctest SKIP) only when no chromium is installed.

Usage: report_browser_test.py REPORT_DIR WORK_DIR [--screenshot FILE --width W --height H]
"""
import argparse
import base64
import json
import os
import re
import shutil
import socket
import subprocess
import sys
import tempfile
import time
import urllib.request

FLAGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-background-networking",
         "--disable-component-update", "--disable-sync", "--no-first-run"]


class WebSocket:
    """The client side of RFC 6455, text frames only: enough for the DevTools protocol."""

    def __init__(self, url):
        m = re.match(r"ws://([^:/]+):(\d+)(/.*)", url)
        self.sock = socket.create_connection((m.group(1), int(m.group(2))), timeout=30)
        key = base64.b64encode(os.urandom(16)).decode()
        self.sock.sendall((f"GET {m.group(3)} HTTP/1.1\r\nHost: {m.group(1)}:{m.group(2)}\r\nUpgrade: websocket\r\n"
                           f"Connection: Upgrade\r\nSec-WebSocket-Key: {key}\r\nSec-WebSocket-Version: 13\r\n\r\n")
                          .encode())
        response = b""
        while b"\r\n\r\n" not in response:
            chunk = self.sock.recv(4096)
            if not chunk:
                raise ConnectionError("DevTools closed the connection during the handshake")
            response += chunk
        if b" 101 " not in response.split(b"\r\n")[0]:
            raise ConnectionError(f"DevTools refused the WebSocket: {response[:200]!r}")
        self.buffer = response.split(b"\r\n\r\n", 1)[1]

    def send(self, text):
        payload = text.encode()
        header = bytes([0x81])
        n = len(payload)
        header += bytes([0x80 | n]) if n < 126 else bytes([0x80 | 126]) + n.to_bytes(2, "big") if n < 65536 \
            else bytes([0x80 | 127]) + n.to_bytes(8, "big")
        mask = os.urandom(4)
        self.sock.sendall(header + mask + bytes(b ^ mask[i % 4] for i, b in enumerate(payload)))

    def _read(self, n):
        while len(self.buffer) < n:
            chunk = self.sock.recv(1 << 20)
            if not chunk:
                raise ConnectionError("DevTools closed the connection")
            self.buffer += chunk
        data, self.buffer = self.buffer[:n], self.buffer[n:]
        return data

    def receive(self):
        message = b""
        while True:
            b0, b1 = self._read(2)
            n = b1 & 0x7F
            if n == 126:
                n = int.from_bytes(self._read(2), "big")
            elif n == 127:
                n = int.from_bytes(self._read(8), "big")
            payload = self._read(n)
            if b0 & 0x0F in (0x1, 0x0):
                message += payload
                if b0 & 0x80:
                    return message.decode()


class DevTools:
    def __init__(self, url):
        self.ws = WebSocket(url)
        self.next_id = 0
        self.events = []

    def call(self, method, **params):
        self.next_id += 1
        self.ws.send(json.dumps({"id": self.next_id, "method": method, "params": params}))
        while True:
            message = json.loads(self.ws.receive())
            if message.get("id") == self.next_id:
                if "error" in message:
                    raise RuntimeError(f"{method}: {message['error']}")
                return message.get("result", {})
            self.events.append(message)

    def wait_for(self, event, seconds):
        end = time.time() + seconds
        while time.time() < end:
            if any(e.get("method") == event for e in self.events):
                return True
            self.events.append(json.loads(self.ws.receive()))
        return False


def start_chromium(chromium, profile):
    process = subprocess.Popen([chromium] + FLAGS + [f"--user-data-dir={profile}", "--remote-debugging-port=0",
                                                     "--window-size=1280,900", "about:blank"],
                               stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    end = time.time() + 60
    port_file = os.path.join(profile, "DevToolsActivePort")
    while time.time() < end:
        if os.path.exists(port_file):
            lines = open(port_file).read().split()
            if lines:
                return process, int(lines[0])
        if process.poll() is not None:
            raise RuntimeError(f"chromium exited ({process.returncode}): {process.stderr.read()[-2000:]}")
        time.sleep(0.1)
    process.kill()
    raise RuntimeError("chromium did not open its DevTools port within 60 s")


def page_target(port):
    end = time.time() + 30
    while time.time() < end:
        targets = json.load(urllib.request.urlopen(f"http://127.0.0.1:{port}/json/list", timeout=10))
        pages = [t for t in targets if t.get("type") == "page"]
        if pages:
            return pages[0]["webSocketDebuggerUrl"]
        time.sleep(0.2)
    raise RuntimeError("chromium has no page target")


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("report")
    parser.add_argument("work")
    parser.add_argument("--screenshot", default=None)
    parser.add_argument("--width", type=int, default=1280)
    parser.add_argument("--height", type=int, default=0, help="0: the whole page")
    args = parser.parse_args()
    chromium = next((c for c in (shutil.which("chromium"), shutil.which("chromium-browser"),
                                 shutil.which("google-chrome")) if c), None)
    if not chromium:
        print("report_browser: SKIPPED: no chromium installed (scripts/setup.sh installs Debian's chromium)")
        return 77
    index = os.path.abspath(os.path.join(args.report, "index.html"))
    if not os.path.isfile(index):
        print(f"report_browser: {index} missing (report_quick makes it)")
        return 1
    os.makedirs(args.work, exist_ok=True)
    profile = tempfile.mkdtemp(prefix="chromium-", dir=args.work)
    process, port = start_chromium(chromium, profile)
    failures = []
    try:
        tools = DevTools(page_target(port))
        for domain in ("Page", "Runtime", "Log", "Network"):
            tools.call(f"{domain}.enable")
        tools.call("Emulation.setDeviceMetricsOverride", width=args.width, height=args.height or 900,
                   deviceScaleFactor=1, mobile=False)
        tools.call("Page.navigate", url="file://" + index)
        if not tools.wait_for("Page.loadEventFired", 60):
            failures.append("the page did not finish loading within 60 s")
        images = tools.call("Runtime.evaluate", returnByValue=True, expression=(
            "Array.from(document.images).map(i => ({src: i.getAttribute('src'), complete: i.complete, "
            "width: i.naturalWidth}))"))["result"]["value"]
        if not images:
            failures.append("the page has no images")
        for image in images:
            if not image["complete"] or image["width"] <= 0:
                failures.append(f"image {image['src']} did not load (naturalWidth {image['width']})")
        for e in tools.events:
            method, params = e.get("method"), e.get("params", {})
            if method == "Runtime.consoleAPICalled" and params.get("type") in ("error", "assert"):
                failures.append(f"console error: {params.get('args')}")
            elif method == "Runtime.exceptionThrown":
                failures.append(f"exception: {params.get('exceptionDetails', {}).get('text')}")
            elif method == "Log.entryAdded" and params.get("entry", {}).get("level") == "error":
                failures.append(f"console error: {params['entry'].get('text')} {params['entry'].get('url', '')}")
            elif method == "Network.loadingFailed":
                failures.append(f"request failed: {params.get('errorText')} ({params.get('type')})")
        shot = {"format": "png"}
        if not args.height:
            size = tools.call("Page.getLayoutMetrics")["cssContentSize"]
            shot["clip"] = {"x": 0, "y": 0, "width": args.width, "height": size["height"], "scale": 1}
            shot["captureBeyondViewport"] = True
        png = base64.b64decode(tools.call("Page.captureScreenshot", **shot)["data"])
        target = args.screenshot or os.path.join(args.work, "screenshot.png")
        with open(target, "wb") as f:
            f.write(png)
        if not png.startswith(b"\x89PNG") or len(png) < 10000:
            failures.append(f"screenshot {target} is not a real PNG ({len(png)} bytes)")
    finally:
        process.terminate()
        try:
            process.wait(timeout=10)
        except subprocess.TimeoutExpired:
            process.kill()
        shutil.rmtree(profile, ignore_errors=True)
    if failures:
        print("\n".join(failures))
        return 1
    print(f"report_browser: {len(images)} images loaded, no console errors, screenshot {target}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
