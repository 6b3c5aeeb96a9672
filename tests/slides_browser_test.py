#!/usr/bin/env python3
"""Opens every slide deck (build/slides/*.html, slides/README.md) in headless Chromium and walks it
slide by slide through the DevTools protocol (a WebSocket client of Python's standard library):

  - every image on a shown slide has decoded (complete, naturalWidth > 0);
  - every formula on a shown slide is MathML that the browser laid out (a <math> box wider and taller
    than 0), and no TeX source is left in the text ($$, \\frac);
  - nothing on a slide lies outside the window (a slide too full);
  - no request left the machine: every URL the page asked for is data:, blob:, about: or the deck's
    own file: (the network is cut as well: every host name resolves to nothing);
  - screenshots of each deck's first slides are written to BUILD/slides/screenshots/.

    slides_browser_test.py SOURCE_DIR BUILD_DIR RASTER

When BUILD_DIR/slides lacks a deck or one is older than slides/'s sources, they are built first (slides/build_deck.py html). Exit 77 (ctest's
skip), saying what is missing, without Chromium, pandoc or slides/node_modules (RASTER_WITH_SLIDES=1
bash .ci/setup installs them).
"""
import base64
import json
import os
import shutil
import socket
import struct
import subprocess
import sys
import tempfile
import time
import urllib.request

SCREENSHOTS_PER_DECK = 3
ALLOWED_SCHEMES = ("data:", "blob:", "about:", "file:")


class WebSocket:
    """A minimal client: text frames out (masked), frames in, continuation frames joined."""

    def __init__(self, url):
        assert url.startswith("ws://")
        host_port, _, path = url[5:].partition("/")
        host, _, port = host_port.partition(":")
        self.sock = socket.create_connection((host, int(port)), timeout=60)
        key = base64.b64encode(os.urandom(16)).decode()
        self.sock.sendall(("GET /%s HTTP/1.1\r\nHost: %s\r\nUpgrade: websocket\r\nConnection: Upgrade\r\n"
                           "Sec-WebSocket-Key: %s\r\nSec-WebSocket-Version: 13\r\n\r\n" % (path, host_port, key)).encode())
        response = b""
        while b"\r\n\r\n" not in response:
            response += self.sock.recv(4096)
        head, _, self.buffer = response.partition(b"\r\n\r\n")
        if b" 101 " not in head.split(b"\r\n")[0]:
            raise RuntimeError("WebSocket handshake failed: %r" % head[:200])

    def send(self, text):
        data = text.encode()
        header = bytes([0x81])
        if len(data) < 126:
            header += bytes([0x80 | len(data)])
        elif len(data) < 65536:
            header += bytes([0x80 | 126]) + struct.pack(">H", len(data))
        else:
            header += bytes([0x80 | 127]) + struct.pack(">Q", len(data))
        mask = os.urandom(4)
        self.sock.sendall(header + mask + bytes(b ^ mask[i % 4] for i, b in enumerate(data)))

    def _read(self, n):
        while len(self.buffer) < n:
            chunk = self.sock.recv(1 << 20)
            if not chunk:
                raise RuntimeError("the browser closed the connection")
            self.buffer += chunk
        out, self.buffer = self.buffer[:n], self.buffer[n:]
        return out

    def receive(self):
        message = b""
        while True:
            b0, b1 = self._read(2)
            n = b1 & 0x7F
            if n == 126:
                n = struct.unpack(">H", self._read(2))[0]
            elif n == 127:
                n = struct.unpack(">Q", self._read(8))[0]
            payload = self._read(n)
            opcode = b0 & 0x0F
            if opcode in (0x8,):
                raise RuntimeError("the browser closed the WebSocket")
            if opcode in (0x9, 0xA):
                continue
            message += payload
            if b0 & 0x80:
                return message.decode()


class Page:
    """One tab, driven through the DevTools protocol; events are kept for inspection."""

    def __init__(self, ws):
        self.ws, self.next_id, self.events = ws, 0, []

    def call(self, method, **params):
        self.next_id += 1
        self.ws.send(json.dumps({"id": self.next_id, "method": method, "params": params}))
        while True:
            message = json.loads(self.ws.receive())
            if message.get("id") == self.next_id:
                if "error" in message:
                    raise RuntimeError("%s: %s" % (method, message["error"]))
                return message.get("result", {})
            self.events.append(message)

    def evaluate(self, expression):
        result = self.call("Runtime.evaluate", expression=expression, returnByValue=True, awaitPromise=True)
        if "exceptionDetails" in result:
            raise RuntimeError("%s: %s" % (expression[:80], result["exceptionDetails"]))
        return result["result"].get("value")


# Run on the shown slide: its images and formulas, as the browser laid them out.
SLIDE_CHECK = """(() => {
  const slide = Reveal.getCurrentSlide();
  const images = [...slide.querySelectorAll('img')].map(i => ({src: i.currentSrc.slice(0, 40),
      ok: i.complete && i.naturalWidth > 0, width: i.naturalWidth}));
  const maths = [...slide.querySelectorAll('math')].map(m => {
      const r = m.getBoundingClientRect(); return {w: r.width, h: r.height}; });
  const text = slide.innerText;
  // Content outside the window: a slide too full, or centred before its images had a size.
  const outside = [...slide.children].filter(e => { const r = e.getBoundingClientRect();
      return r.height > 0 && (r.top < -1 || r.bottom > innerHeight + 1); }).map(e => e.tagName);
  return {title: (slide.querySelector('h1,h2') || {}).innerText || '', images, maths, outside,
          tex: text.includes('$$') || text.includes('\\\\frac')};
})()"""


def start_chromium(profile):
    chromium = shutil.which("chromium") or shutil.which("chromium-browser")
    command = [chromium, "--headless", "--no-sandbox", "--disable-gpu", "--no-first-run",
               "--disable-background-networking", "--disable-component-update", "--disable-sync",
               "--host-resolver-rules=MAP * ~NOTFOUND , EXCLUDE 127.0.0.1",
               "--remote-debugging-port=0", "--user-data-dir=" + profile, "--window-size=1280,720",
               "--allow-file-access-from-files", "about:blank"]
    process = subprocess.Popen(command, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    port_file = os.path.join(profile, "DevToolsActivePort")
    for _ in range(300):
        if os.path.isfile(port_file) and open(port_file).read().count("\n") >= 1:
            break
        time.sleep(0.1)
    else:
        process.kill()
        raise RuntimeError("Chromium wrote no DevToolsActivePort in 30 s")
    port = int(open(port_file).read().split("\n")[0])
    for _ in range(50):
        targets = json.load(urllib.request.urlopen("http://127.0.0.1:%d/json/list" % port))
        pages = [t for t in targets if t.get("type") == "page"]
        if pages:
            return process, pages[0]["webSocketDebuggerUrl"]
        time.sleep(0.1)
    process.kill()
    raise RuntimeError("Chromium opened no page")


def walk_deck(page, path, shots_dir):
    """Problems found in one deck, and its slide count."""
    problems = []
    name = os.path.splitext(os.path.basename(path))[0]
    page.events.clear()
    page.call("Page.navigate", url="file://" + path)
    for _ in range(200):
        if page.evaluate("typeof Reveal !== 'undefined' && Reveal.isReady && Reveal.isReady()"):
            break
        time.sleep(0.05)
    else:
        return ["%s: reveal.js never became ready" % name], 0
    page.evaluate("new Promise(r => { if (document.readyState === 'complete') r(); else addEventListener('load', () => r()); })")
    total = page.evaluate("Reveal.getTotalSlides()")
    images = maths = 0
    for k in range(total):
        page.evaluate("Reveal.slide(%d, 0)" % k)
        page.evaluate("new Promise(r => requestAnimationFrame(() => requestAnimationFrame(r)))")
        slide = page.evaluate(SLIDE_CHECK)
        where = "%s slide %d (%s)" % (name, k + 1, slide["title"])
        for image in slide["images"]:
            images += 1
            if not image["ok"]:
                problems.append("%s: image %s... did not decode" % (where, image["src"]))
        for m in slide["maths"]:
            maths += 1
            if not (m["w"] > 0 and m["h"] > 0):
                problems.append("%s: a formula laid out as %gx%g" % (where, m["w"], m["h"]))
        if slide["outside"]:
            problems.append("%s: %s outside the window" % (where, ", ".join(slide["outside"])))
        if slide["tex"]:
            problems.append("%s: TeX source left in the text" % where)
        if k < SCREENSHOTS_PER_DECK:
            shot = page.call("Page.captureScreenshot", format="png")
            with open(os.path.join(shots_dir, "%s-%d.png" % (name, k + 1)), "wb") as f:
                f.write(base64.b64decode(shot["data"]))
    for event in page.events:
        if event.get("method") == "Network.requestWillBeSent":
            url = event["params"]["request"]["url"]
            if not url.startswith(ALLOWED_SCHEMES) or (url.startswith("file:") and not url.startswith("file://" + path)):
                problems.append("%s: a request for %s" % (name, url[:120]))
    print("%s: %d slides, %d images decoded, %d formulas laid out" % (name, total, images, maths))
    return problems, total


def main(source_dir, build_dir, raster):
    missing = [what for what, ok in [
        ("chromium", shutil.which("chromium") or shutil.which("chromium-browser")),
        ("pandoc", shutil.which("pandoc")),
        ("slides/node_modules/reveal.js (npm ci in slides/)",
         os.path.isfile(os.path.join(source_dir, "slides", "node_modules", "reveal.js", "dist", "reveal.js")))] if not ok]
    if missing:
        print("slides_browser: SKIPPED, not installed: %s (RASTER_WITH_SLIDES=1 bash .ci/setup)" % ", ".join(missing))
        return 77
    sys.path.insert(0, os.path.join(source_dir, "slides"))
    import build_deck
    out = os.path.join(build_dir, "slides")
    decks = [os.path.join(out, d + ".html") for d in build_deck.DECKS]
    sources = [os.path.join(source_dir, "slides", n) for n in os.listdir(os.path.join(source_dir, "slides"))
               if n.endswith((".md", ".txt", ".css", ".py"))]
    newest_source = max(os.path.getmtime(s) for s in sources)
    if not all(os.path.isfile(d) and os.path.getmtime(d) >= newest_source for d in decks):
        print("slides_browser: building the decks into %s (missing or older than slides/)" % out)
        build_deck.html(raster, out)
    shots_dir = os.path.join(out, "screenshots")
    os.makedirs(shots_dir, exist_ok=True)
    problems, slides = [], 0
    with tempfile.TemporaryDirectory(ignore_cleanup_errors=True) as profile:
        process, url = start_chromium(profile)
        try:
            page = Page(WebSocket(url))
            page.call("Page.enable")
            page.call("Network.enable")
            page.call("Emulation.setDeviceMetricsOverride", width=1280, height=720, deviceScaleFactor=1, mobile=False)
            for deck in decks:
                found, total = walk_deck(page, os.path.abspath(deck), shots_dir)
                problems += found
                slides += total
        finally:
            process.terminate()
            process.wait(timeout=10)
    for p in problems:
        print("FAIL " + p)
    if slides == 0:
        print("FAIL no slides walked")
        return 1
    print("slides_browser: %d decks, %d slides, screenshots in %s: %s" %
          (len(decks), slides, shots_dir, "FAIL" if problems else "all good"))
    return 1 if problems else 0


if __name__ == "__main__":
    if len(sys.argv) != 4:
        print(__doc__)
        sys.exit(2)
    sys.exit(main(*sys.argv[1:]))
