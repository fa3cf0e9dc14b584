// A small reader of MCAP files (https://mcap.dev/spec): the records a
// learnpnp recording holds (Header, Schema, Channel, Message, uncompressed
// Chunk, Footer; others skipped). Returns every message with its channel's
// topic and log time (nanoseconds as a BigInt), in log-time order.
"use strict";

const LearnpnpMcap = (() => {
  const MAGIC = [0x89, 0x4d, 0x43, 0x41, 0x50, 0x30, 0x0d, 0x0a];
  const OP = { header: 0x01, footer: 0x02, schema: 0x03, channel: 0x04, message: 0x05, chunk: 0x06 };
  const utf8 = new TextDecoder();

  class Cursor {
    constructor(view, offset, end) {
      this.view = view;
      this.offset = offset;
      this.end = end;
    }
    need(n) {
      if (this.offset + n > this.end) throw new Error(`MCAP record truncated at byte ${this.offset}`);
    }
    u8() { this.need(1); return this.view.getUint8(this.offset++); }
    u16() { this.need(2); const v = this.view.getUint16(this.offset, true); this.offset += 2; return v; }
    u32() { this.need(4); const v = this.view.getUint32(this.offset, true); this.offset += 4; return v; }
    u64() { this.need(8); const v = this.view.getBigUint64(this.offset, true); this.offset += 8; return v; }
    length64() {
      const v = this.u64();
      if (v > BigInt(this.end - this.offset)) throw new Error(`MCAP length ${v} runs past the data at byte ${this.offset}`);
      return Number(v);
    }
    bytes(n) {
      this.need(n);
      const b = new Uint8Array(this.view.buffer, this.view.byteOffset + this.offset, n);
      this.offset += n;
      return b;
    }
    string() { return utf8.decode(this.bytes(this.u32())); }
  }

  // Reads the records between `offset` and `end` of `view` into `out`; stops
  // at the Footer or the closing magic.
  function records(view, offset, end, out) {
    const c = new Cursor(view, offset, end);
    while (c.offset < c.end) {
      if (c.end - c.offset === MAGIC.length && MAGIC.every((b, i) => view.getUint8(c.offset + i) === b)) return true;
      const op = c.u8();
      const len = c.length64();
      const body = new Cursor(view, c.offset, c.offset + len);
      c.offset += len;
      if (op === OP.schema) {
        const id = body.u16();
        out.schemas.set(id, { name: body.string(), encoding: body.string() });
      } else if (op === OP.channel) {
        const id = body.u16();
        const schemaId = body.u16();
        const topic = body.string();
        const encoding = body.string();
        out.channels.set(id, { id, schemaId, topic, encoding });
      } else if (op === OP.message) {
        const channelId = body.u16();
        body.u32(); // sequence
        const logTime = body.u64();
        body.u64(); // publish time
        out.messages.push({ channelId, logTime, data: body.bytes(body.end - body.offset) });
      } else if (op === OP.chunk) {
        body.u64(); // message start time
        body.u64(); // message end time
        body.u64(); // uncompressed size
        body.u32(); // uncompressed CRC
        const compression = body.string();
        const size = body.length64();
        if (compression !== "") {
          const e = new Error(`MCAP chunk compressed with "${compression}": this page reads uncompressed chunks only`);
          e.unsupported = true;
          throw e;
        }
        records(view, body.offset, body.offset + size, out);
      } else if (op === OP.footer) {
        return true;
      }
    }
    return false;
  }

  // Parses a whole MCAP file held in `buffer` (an ArrayBuffer).
  function read(buffer) {
    const view = new DataView(buffer);
    if (view.byteLength < MAGIC.length || MAGIC.some((b, i) => view.getUint8(i) !== b)) {
      throw new Error("not an MCAP file (bad magic)");
    }
    const out = { schemas: new Map(), channels: new Map(), messages: [] };
    // A recording still being written has no footer and may end inside a
    // record: what was read before that is kept, and the file marked truncated.
    let truncated = false;
    try {
      truncated = !records(view, MAGIC.length, view.byteLength, out);
    } catch (e) {
      if (out.messages.length === 0 || e.unsupported) throw e;
      truncated = true;
    }
    const messages = out.messages
      .filter((m) => out.channels.has(m.channelId))
      .map((m) => ({ topic: out.channels.get(m.channelId).topic, logTime: m.logTime, data: m.data }));
    messages.sort((a, b) => (a.logTime < b.logTime ? -1 : a.logTime > b.logTime ? 1 : 0));
    return { channels: out.channels, schemas: out.schemas, messages, truncated };
  }

  return { read };
})();
