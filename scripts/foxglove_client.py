"""A minimal Foxglove WebSocket client (stdlib only): subscribes to the
channels named after HOST PORT (every channel when none is named) and reads
until the server closes. Prints the messages received.

    python3 foxglove_client.py HOST PORT [TOPIC ...]
"""
import base64, json, os, socket, struct, sys, time

host, port = sys.argv[1], int(sys.argv[2])
topics = set(sys.argv[3:])
deadline = time.time() + 30
while True:
    try:
        s = socket.create_connection((host, port))
        break
    except OSError:
        if time.time() > deadline:
            raise
        time.sleep(0.05)
key = base64.b64encode(os.urandom(16)).decode()
s.sendall((f"GET / HTTP/1.1\r\nHost: {host}:{port}\r\nUpgrade: websocket\r\nConnection: Upgrade\r\n"
           f"Sec-WebSocket-Key: {key}\r\nSec-WebSocket-Version: 13\r\nSec-WebSocket-Protocol: foxglove.sdk.v1\r\n\r\n").encode())
buf = b""
while b"\r\n\r\n" not in buf:
    buf += s.recv(4096)
head, buf = buf.split(b"\r\n\r\n", 1)
assert b" 101 " in head.split(b"\r\n")[0], head

# The bytes received and not yet parsed: buf[pos:]. Parsing moves pos on and
# drops what was parsed only when more is needed, so that a frame costs its
# own bytes, not a copy of everything received after it.
pos = 0


def need(n):
    global buf, pos
    while len(buf) - pos < n:
        chunk = s.recv(262144)
        if not chunk:
            raise EOFError
        buf = buf[pos:] + chunk
        pos = 0


def frame():
    global pos
    need(2)
    op, ln = buf[pos] & 0x0F, buf[pos + 1] & 0x7F
    off = 2
    if ln == 126:
        need(4); ln = struct.unpack_from(">H", buf, pos + 2)[0]; off = 4
    elif ln == 127:
        need(10); ln = struct.unpack_from(">Q", buf, pos + 2)[0]; off = 10
    need(off + ln)
    data = buf[pos + off:pos + off + ln]
    pos += off + ln
    return op, data


def send_text(text):
    data = text.encode()
    mask = os.urandom(4)
    hdr = bytes([0x81]) + (bytes([0x80 | len(data)]) if len(data) < 126 else bytes([0x80 | 126]) + struct.pack(">H", len(data)))
    s.sendall(hdr + mask + bytes(b ^ mask[i % 4] for i, b in enumerate(data)))

# The feed's eight channels and the page's bundle.
advertised, ids = 0, []
while advertised < 9:
    op, data = frame()
    if op == 1:
        msg = json.loads(data)
        if msg.get("op") == "advertise":
            advertised += len(msg["channels"])
            ids += [c["id"] for c in msg["channels"] if not topics or c["topic"] in topics]
send_text(json.dumps({"op": "subscribe", "subscriptions": [{"id": i, "channelId": i} for i in ids]}))
print("subscribed", flush=True)
count = 0
try:
    while True:
        op, data = frame()
        if op == 2:
            count += 1
        elif op == 8:
            break
except (EOFError, ConnectionResetError):
    pass
import resource
cpu = resource.getrusage(resource.RUSAGE_SELF)
print("messages", count, "client_cpu_s", round(cpu.ru_utime + cpu.ru_stime, 2), flush=True)
