#include "sarloc/dds/writer_authority.hpp"

#include <openssl/evp.h>
#include <openssl/x509.h>

#include <algorithm>
#include <memory>

#include "sarloc/core/common/errors.hpp"
#include "sarloc/dds/dds_error.hpp"
#include "sarloc/dds/participant.hpp"

namespace sarloc::dds {
namespace {

constexpr std::size_t kDevicesCached = 4096;

bool prefix_matches(const IdentityPrefix& prefix, const std::uint8_t* guid) {
  return std::equal(prefix.begin(), prefix.end(), guid);
}

std::string hex_of(const std::uint8_t* bytes, std::size_t n) {
  static const char* digits = "0123456789abcdef";
  std::string text;
  for (std::size_t i = 0; i < n; ++i) {
    text += digits[bytes[i] >> 4];
    text += digits[bytes[i] & 0xF];
  }
  return text;
}

}  // namespace

IdentityPrefix identity_prefix_of(const std::string& node_id) {
  const std::unique_ptr<X509_NAME, decltype(&X509_NAME_free)> name(X509_NAME_new(), X509_NAME_free);
  unsigned char md[EVP_MAX_MD_SIZE];
  unsigned int length = 0;
  const auto* organisation = reinterpret_cast<const unsigned char*>("sarloc");
  const auto* common_name = reinterpret_cast<const unsigned char*>(node_id.c_str());
  if (!name || X509_NAME_add_entry_by_txt(name.get(), "O", MBSTRING_UTF8, organisation, -1, -1, 0) != 1 ||
      X509_NAME_add_entry_by_txt(name.get(), "CN", MBSTRING_UTF8, common_name, -1, -1, 0) != 1 ||
      X509_NAME_digest(name.get(), EVP_sha256(), md, &length) != 1 || length < 6) {
    throw DdsError("cannot compute the DDS identity of '" + node_id + "' (OpenSSL)");
  }
  // The flag bit, then the digest's first 47 bits (Fast DDS PKIDH adjust_participant_key).
  IdentityPrefix prefix{};
  prefix[0] = static_cast<std::uint8_t>(0x80 | (md[0] >> 1));
  for (std::size_t i = 1; i < prefix.size(); ++i) {
    prefix[i] = static_cast<std::uint8_t>((md[i - 1] << 7) | (md[i] >> 1));
  }
  return prefix;
}

bool proves_identity(const Participant& participant, const std::string& node_id) {
  return prefix_matches(identity_prefix_of(node_id), participant.get()->guid().guidPrefix.value);
}

void require_identity(const Participant& participant, const std::string& node_id, const std::string& key) {
  if (!participant.secured() || proves_identity(participant, node_id)) return;
  throw ConfigError(key + " = '" + node_id + "': this node's DDS Security certificate is not O=sarloc, CN=" + node_id +
                    " (deploy/security/make-certs.sh issues it so); the other nodes would refuse what it writes about "
                    "responders");
}

WriterAuthority::WriterAuthority(std::shared_ptr<const Participant> participant)
    : participant_(std::move(participant)), secured_(participant_->secured()) {
  if (!secured_) return;
  for (const auto& id : participant_->config().core_node_ids) cores_.emplace_back(id, identity_prefix_of(id));
}

IdentityPrefix WriterAuthority::prefix_of(const std::string& node_id) const {
  std::lock_guard<std::mutex> lock(mutex_);
  const auto it = devices_.find(node_id);
  if (it != devices_.end()) return it->second;
  if (devices_.size() >= kDevicesCached) devices_.clear();  // ids are bounded by the roster, not by senders
  return devices_.emplace(node_id, identity_prefix_of(node_id)).first->second;
}

bool WriterAuthority::admits(const eprosima::fastrtps::rtps::InstanceHandle_t& writer, const std::string& responder_id,
                             Speakers speakers) const {
  if (!secured_ || participant_->is_own_writer(writer)) return true;
  if (prefix_matches(prefix_of(responder_id), writer.value)) return true;
  if (speakers != Speakers::kDeviceOrCore) return false;
  return std::any_of(cores_.begin(), cores_.end(), [&](const auto& core) { return prefix_matches(core.second, writer.value); });
}

std::string WriterAuthority::writer_name(const eprosima::fastrtps::rtps::InstanceHandle_t& writer) const {
  for (const auto& [id, prefix] : cores_) {
    if (prefix_matches(prefix, writer.value)) return id;
  }
  {
    std::lock_guard<std::mutex> lock(mutex_);
    for (const auto& [id, prefix] : devices_) {
      if (prefix_matches(prefix, writer.value)) return id;
    }
  }
  return "participant " + hex_of(writer.value, 12);
}

std::string WriterAuthority::refusal(const std::string& what, const eprosima::fastrtps::rtps::InstanceHandle_t& writer,
                                     const std::string& responder_id) const {
  return what + " about '" + responder_id + "' written by " + writer_name(writer) +
         ", which may not speak for it (DDS Security identity)";
}

}  // namespace sarloc::dds
