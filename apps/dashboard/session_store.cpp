#include "session_store.hpp"

#include <algorithm>
#include <random>

namespace sarloc::dashboard {

bool same_secret(const std::string& given, const std::string& expected) {
  if (expected.empty() || given.size() != expected.size()) return false;
  unsigned char difference = 0;
  for (std::size_t i = 0; i < expected.size(); ++i) difference |= static_cast<unsigned char>(given[i] ^ expected[i]);
  return difference == 0;
}

std::string random_secret(int bits) {
  std::random_device device;
  static constexpr char kHex[] = "0123456789abcdef";
  std::string secret;
  for (int i = 0; i < bits / 4; ++i) secret += kHex[device() & 0xF];
  return secret;
}

SessionStore::SessionStore(std::string view_token, std::string operator_token, std::chrono::hours lifetime,
                           std::size_t max_sessions)
    : view_token_(std::move(view_token)),
      operator_token_(std::move(operator_token)),
      lifetime_(lifetime),
      max_sessions_(max_sessions) {}

bool SessionStore::may_view(const std::string& token) const {
  return same_secret(token, view_token_) || same_secret(token, operator_token_);
}

bool SessionStore::may_act(const std::string& token) const { return same_secret(token, operator_token_); }

namespace {
std::string bearer_token(const std::string& authorization) {
  const std::string prefix = "Bearer ";
  return authorization.rfind(prefix, 0) == 0 ? authorization.substr(prefix.size()) : std::string();
}
}  // namespace

bool SessionStore::may_view_bearer(const std::string& authorization) const { return may_view(bearer_token(authorization)); }

bool SessionStore::may_act_bearer(const std::string& authorization) const { return may_act(bearer_token(authorization)); }

std::string SessionStore::open() {
  std::string id = random_secret(128);
  std::lock_guard<std::mutex> lock(mutex_);
  const auto now = std::chrono::steady_clock::now();
  for (auto it = sessions_.begin(); it != sessions_.end();) it = now - it->second > lifetime_ ? sessions_.erase(it) : std::next(it);
  if (sessions_.size() >= max_sessions_) {
    sessions_.erase(std::min_element(sessions_.begin(), sessions_.end(),
                                     [](const auto& a, const auto& b) { return a.second < b.second; }));
  }
  sessions_[id] = now;
  return id;
}

bool SessionStore::has_session(const std::string& cookie_header) const {
  // "a=1; sarloc_session=ID; b=2"
  const std::string key = std::string(kCookie) + "=";
  for (std::size_t at = 0; at < cookie_header.size();) {
    while (at < cookie_header.size() && (cookie_header[at] == ' ' || cookie_header[at] == ';')) ++at;
    const std::size_t end = std::min(cookie_header.find(';', at), cookie_header.size());
    if (cookie_header.compare(at, key.size(), key) == 0) {
      const std::string id = cookie_header.substr(at + key.size(), end - at - key.size());
      std::lock_guard<std::mutex> lock(mutex_);
      const auto it = sessions_.find(id);
      if (it != sessions_.end() && std::chrono::steady_clock::now() - it->second <= lifetime_) return true;
    }
    at = end;
  }
  return false;
}

std::string SessionStore::set_cookie(const std::string& session, bool secure) {
  return std::string(kCookie) + "=" + session + "; Path=/; HttpOnly; SameSite=Strict" + (secure ? "; Secure" : "");
}

}  // namespace sarloc::dashboard
