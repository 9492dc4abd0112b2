#include "sarloc/recording/mcap_recovery.hpp"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <map>

#include "sarloc/recording/mcap_reader.hpp"
#include "sarloc/recording/mcap_writer.hpp"

namespace sarloc::recording {

RecoveryResult recover_mcap(const std::string& path, Compression compression) {
  // First pass: is anything wrong at all?
  const McapReadResult check = read_mcap(path, McapVisitor{});
  RecoveryResult result;
  result.damage = check.damage;
  result.bytes_lost = check.file_size - check.good_bytes;
  if (check.complete) {
    result.was_complete = true;
    result.messages = check.messages;
    return result;
  }

  const std::string temporary = path + ".recovering";
  {
    McapWriterOptions options;
    options.profile = check.header.profile.rfind("x-", 0) == 0 ? check.header.profile : "x-sarloc";
    options.library = check.header.library.empty() ? "sarloc (recovered)" : check.header.library + " (recovered)";
    options.compression = compression;
    McapWriter writer(temporary, options);
    std::map<std::uint16_t, std::uint16_t> schema_ids;
    std::map<std::uint16_t, std::uint16_t> channel_ids;
    McapVisitor copy;
    copy.on_schema = [&](const Schema& schema) {
      if (!schema_ids.count(schema.id)) schema_ids[schema.id] = writer.add_schema(schema.name, schema.encoding, schema.data);
    };
    copy.on_channel = [&](const Channel& channel) {
      if (channel_ids.count(channel.id)) return;
      const auto schema = schema_ids.find(channel.schema_id);
      channel_ids[channel.id] = writer.add_channel(channel.topic, schema == schema_ids.end() ? 0 : schema->second,
                                                   channel.message_encoding, channel.metadata);
    };
    copy.on_message = [&](const Message& message) {
      const auto channel = channel_ids.find(message.channel_id);
      if (channel == channel_ids.end()) return;  // its channel record was lost: nothing to decode it with
      writer.write(channel->second, message.sequence, message.log_time_ns, message.publish_time_ns,
                   message.data.data(), message.data.size());
      ++result.messages;
    };
    copy.on_metadata = [&](const Metadata& metadata) { writer.write_metadata(metadata); };
    read_mcap(path, copy);
    writer.write_metadata({"sarloc.recovery",
                           {{"damage", check.damage},
                            {"bytes_lost", std::to_string(result.bytes_lost)},
                            {"messages_kept", std::to_string(result.messages)}}});
    writer.close();
  }
  // The rewritten file must read back whole before it replaces anything.
  const McapReadResult verify = read_mcap(temporary, McapVisitor{});
  if (!verify.complete || verify.messages != result.messages) {
    std::remove(temporary.c_str());
    throw RecordingError("recovery of '" + path + "' did not produce a whole file: " + verify.damage);
  }
  const std::string damaged = path + ".damaged";
  if (std::rename(path.c_str(), damaged.c_str()) != 0 || std::rename(temporary.c_str(), path.c_str()) != 0) {
    throw RecordingError("cannot replace '" + path + "' with its recovered copy: " + std::strerror(errno));
  }
  return result;
}

}  // namespace sarloc::recording
