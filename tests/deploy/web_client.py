#!/usr/bin/env python3
"""A browser's view of an installed hullpose-web, without a browser (the page itself is tested in
a real one by tests/consumers/web_browser_test.sh): fetches the page and three.js over HTTP, then
reads the WebSocket until the skeletons of every trigger came.

usage: web_client.py PORT FRAMES OUT
  OUT.page   the page as served          OUT.ready  written once the WebSocket is open
  OUT        {"skeletons", "valid", "statuses", "sequences"} as JSON
Exit status 0 when every sequence 0..FRAMES-1 came once with 25 joints; 1 otherwise.
"""
import base64
import http.client
import json
import os
import socket
import struct
import sys


def get(port, path):
    c = http.client.HTTPConnection("127.0.0.1", port, timeout=30)
    c.request("GET", path)
    r = c.getresponse()
    body = r.read()
    if r.status != 200 or not body:
        sys.exit(f"web_client: GET {path}: HTTP {r.status}, {len(body)} bytes")
    return body


def read_exact(s, n):
    data = b""
    while len(data) < n:
        chunk = s.recv(n - len(data))
        if not chunk:
            raise EOFError("the server closed the WebSocket")
        data += chunk
    return data


def send_frame(s, opcode, payload):
    # Client frames are masked (RFC 6455 5.3); payloads here are short control frames.
    mask = os.urandom(4)
    s.sendall(bytes([0x80 | opcode, 0x80 | len(payload)]) + mask +
              bytes(b ^ mask[i % 4] for i, b in enumerate(payload)))


def read_message(s):
    while True:
        b0, b1 = read_exact(s, 2)
        n = b1 & 0x7F
        if n == 126:
            (n,) = struct.unpack(">H", read_exact(s, 2))
        elif n == 127:
            (n,) = struct.unpack(">Q", read_exact(s, 8))
        payload = read_exact(s, n)
        opcode = b0 & 0x0F
        if opcode == 0x9:  # ping: answer, or the server closes an idle browser
            send_frame(s, 0xA, payload)
        elif opcode == 0x8:
            raise EOFError("the server closed the WebSocket")
        elif opcode == 0x1:
            return json.loads(payload)


def main():
    port, frames, out = int(sys.argv[1]), int(sys.argv[2]), sys.argv[3]
    with open(out + ".page", "wb") as f:
        f.write(get(port, "/"))
    for path in ("/app.js", "/three/three.min.js", "/three/OrbitControls.js", "/rig.json"):
        get(port, path)
    s = socket.create_connection(("127.0.0.1", port), timeout=60)
    key = base64.b64encode(os.urandom(16)).decode()
    s.sendall((f"GET /ws HTTP/1.1\r\nHost: 127.0.0.1:{port}\r\nUpgrade: websocket\r\n"
               f"Connection: Upgrade\r\nSec-WebSocket-Key: {key}\r\nSec-WebSocket-Version: 13\r\n\r\n").encode())
    head = b""
    while b"\r\n\r\n" not in head:
        head += read_exact(s, 1)
    if b" 101 " not in head.split(b"\r\n")[0]:
        sys.exit(f"web_client: no WebSocket: {head.decode(errors='replace')}")
    open(out + ".ready", "w").close()
    seqs, valid, statuses = [], 0, 0
    while len(seqs) < frames:
        m = read_message(s)
        if m.get("type") == "status":
            statuses += 1
        elif m.get("type") == "skeleton":
            if len(m["joints"]) != 25:
                sys.exit(f"web_client: a skeleton with {len(m['joints'])} joints")
            seqs.append(m["seq"])
            valid += bool(m["valid"])
    summary = {"skeletons": len(seqs), "valid": valid, "statuses": statuses, "sequences": sorted(seqs)}
    with open(out, "w") as f:
        json.dump(summary, f)
    if sorted(seqs) != list(range(frames)):
        sys.exit(f"web_client: sequences {sorted(seqs)}, expected 0..{frames - 1} once each")


if __name__ == "__main__":
    main()
