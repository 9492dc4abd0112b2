// An independent reader of a sarloc recording: the MCAP project's own TypeScript reader
// (@mcap/core, indexed: it checks the footer, summary CRC and every chunk CRC) and Foxglove's
// OMG IDL parser and CDR reader, decoding every message from the schema stored in the file.
//
//   node tests/js/check_mcap.mjs FILE.mcap   -> one JSON report on stdout; exit 0 if all is well
//
// The report: header, statistics, per channel (topic, schema, encodings, metadata, count,
// decode failures, the first and last decoded message), metadata records, errors.
import { McapIndexedReader, McapStreamReader } from "@mcap/core";
import { FileHandleReadable } from "@mcap/nodejs";
import { loadDecompressHandlers } from "@mcap/support";
import { parseIDL } from "@foxglove/omgidl-parser";
import { MessageReader } from "@foxglove/omgidl-serialization";
import fs from "node:fs/promises";

const path = process.argv[2];
if (!path) {
  console.error("usage: node check_mcap.mjs FILE.mcap");
  process.exit(2);
}

// BigInt and typed arrays as plain JSON.
const plain = (value) =>
  JSON.parse(
    JSON.stringify(value, (_, v) => {
      if (typeof v === "bigint") return Number(v);
      if (ArrayBuffer.isView(v)) return Array.from(v);
      return v;
    }),
  );

const report = { file: path, errors: [], channels: {}, metadata: {} };
const decompressHandlers = await loadDecompressHandlers();
const handle = await fs.open(path);
try {
  const reader = await McapIndexedReader.Initialize({ readable: new FileHandleReadable(handle), decompressHandlers });
  report.header = reader.header;
  report.statistics = plain(reader.statistics);
  report.chunks = reader.chunkIndexes.length;
  const decoders = new Map();
  for (const channel of reader.channelsById.values()) {
    const schema = reader.schemasById.get(channel.schemaId);
    const entry = {
      topic: channel.topic,
      messageEncoding: channel.messageEncoding,
      schemaName: schema?.name ?? "",
      schemaEncoding: schema?.encoding ?? "",
      metadata: Object.fromEntries(channel.metadata),
      count: 0,
      decodeFailures: 0,
    };
    report.channels[channel.topic] = entry;
    if (channel.messageEncoding === "cdr") {
      try {
        const definitions = parseIDL(new TextDecoder().decode(schema.data));
        decoders.set(channel.id, new MessageReader(schema.name, definitions));
      } catch (error) {
        report.errors.push(`schema ${schema?.name} of ${channel.topic} does not parse: ${error.message}`);
      }
    } else if (channel.messageEncoding === "json") {
      decoders.set(channel.id, { readMessage: (bytes) => JSON.parse(new TextDecoder().decode(bytes)) });
    }
  }
  for await (const message of reader.readMessages({ validateCrcs: true })) {
    const channel = reader.channelsById.get(message.channelId);
    const entry = report.channels[channel.topic];
    entry.count += 1;
    const decoder = decoders.get(message.channelId);
    try {
      if (!decoder) throw new Error("no decoder");
      const decoded = plain(decoder.readMessage(message.data));
      if (entry.count === 1) entry.first = decoded;
      entry.last = decoded;
    } catch (error) {
      entry.decodeFailures += 1;
      if (entry.decodeFailures === 1) report.errors.push(`${channel.topic}: a message does not decode: ${error.message}`);
    }
  }
  report.metadataIndexes = reader.metadataIndexes.length;
  for await (const record of reader.readMetadata()) {
    report.metadata[record.name] = Object.fromEntries(record.metadata);
  }
  // The per-channel counts of the statistics record must equal what was read.
  for (const [id, count] of reader.statistics?.channelMessageCounts ?? []) {
    const topic = reader.channelsById.get(id)?.topic;
    if (report.channels[topic]?.count !== Number(count)) {
      report.errors.push(`${topic}: statistics say ${count} messages, ${report.channels[topic]?.count} read`);
    }
  }
} catch (error) {
  report.errors.push(`indexed reader: ${error.message}`);
} finally {
  await handle.close();
}

// The streaming reader, front to back, with every CRC checked (the data section's too).
try {
  const stream = new McapStreamReader({ decompressHandlers, validateCrcs: true });
  stream.append(await fs.readFile(path));
  let records = 0;
  while (stream.nextRecord()) records += 1;
  if (!stream.done()) report.errors.push("stream reader: the file does not end properly");
  report.streamRecords = records;
} catch (error) {
  report.errors.push(`stream reader: ${error.message}`);
}

console.log(JSON.stringify(report, null, 1));
process.exit(report.errors.length === 0 ? 0 : 1);
