"""A minimal Foxglove WebSocket client (stdlib only): subscribes to every
channel and reads until the server closes. Prints the messages received."""
import base64, json, os, socket, struct, sys, time

host, port = sys.argv[1], int(sys.argv[2])
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

def need(n):
    global buf
    while len(buf) < n:
        chunk = s.recv(65536)
        if not chunk:
            raise EOFError
        buf += chunk

def frame():
    global buf
    need(2)
    op, ln = buf[0] & 0x0F, buf[1] & 0x7F
    off = 2
    if ln == 126:
        need(4); ln = struct.unpack(">H", buf[2:4])[0]; off = 4
    elif ln == 127:
        need(10); ln = struct.unpack(">Q", buf[2:10])[0]; off = 10
    need(off + ln)
    data = buf[off:off + ln]
    buf = buf[off + ln:]
    return op, data

def send_text(text):
    data = text.encode()
    mask = os.urandom(4)
    hdr = bytes([0x81]) + (bytes([0x80 | len(data)]) if len(data) < 126 else bytes([0x80 | 126]) + struct.pack(">H", len(data)))
    s.sendall(hdr + mask + bytes(b ^ mask[i % 4] for i, b in enumerate(data)))

ids = []
while len(ids) < 8:
    op, data = frame()
    if op == 1:
        msg = json.loads(data)
        if msg.get("op") == "advertise":
            ids += [c["id"] for c in msg["channels"]]
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
print("messages", count, flush=True)
