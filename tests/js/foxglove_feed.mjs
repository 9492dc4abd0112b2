// A Foxglove client on sarloc-dashboard's feed (npm @foxglove/ws-protocol, the protocol's own
// client; Node's WebSocket: run with --experimental-websocket): subscribes to every advertised
// channel, decodes each message from the advertised omgidl schema with Foxglove's decoder.
//
//   node --experimental-websocket tests/js/foxglove_feed.mjs ws://HOST:PORT SECONDS -> JSON
import wsProtocol from "@foxglove/ws-protocol";
import { parseIDL } from "@foxglove/omgidl-parser";
import { MessageReader } from "@foxglove/omgidl-serialization";

const { FoxgloveClient } = wsProtocol;  // a CommonJS package
const [url, seconds = "8"] = process.argv.slice(2);
const result = { errors: [], serverName: null, channels: {}, subprotocol: null };
const plain = (value) => JSON.parse(JSON.stringify(value, (_, v) => (typeof v === "bigint" ? Number(v) : ArrayBuffer.isView(v) ? Array.from(v) : v)));
const ws = new WebSocket(url, [FoxgloveClient.SUPPORTED_SUBPROTOCOL]);
const client = new FoxgloveClient({ ws });
const bySubscription = new Map();
client.on("serverInfo", (info) => { result.serverName = info.name; result.subprotocol = ws.protocol; });
client.on("error", (e) => result.errors.push(`client: ${e.message ?? e}`));
client.on("advertise", (channels) => {
  for (const c of channels) {
    const entry = { topic: c.topic, encoding: c.encoding, schemaName: c.schemaName, schemaEncoding: c.schemaEncoding, count: 0, decodeFailures: 0 };
    result.channels[c.topic] = entry;
    try {
      const reader = new MessageReader(c.schemaName, parseIDL(c.schema));
      bySubscription.set(client.subscribe(c.id), { entry, reader });
    } catch (e) {
      result.errors.push(`${c.topic}: schema does not parse: ${e.message}`);
    }
  }
});
client.on("message", ({ subscriptionId, data }) => {
  const s = bySubscription.get(subscriptionId);
  if (!s) return;
  s.entry.count += 1;
  try {
    s.entry.last = plain(s.reader.readMessage(new Uint8Array(data.buffer, data.byteOffset, data.byteLength)));
  } catch (e) {
    s.entry.decodeFailures += 1;
  }
});
await new Promise((resolve) => setTimeout(resolve, Number(seconds) * 1000));
client.close();
console.log(JSON.stringify(result));
process.exit(result.errors.length === 0 ? 0 : 1);
