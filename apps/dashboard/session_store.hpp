#pragma once
// Who may look at the picture: the view token, the operator token, or a session opened with
// either (an HttpOnly cookie, so that the token leaves the address bar after its first use).
// Shared by the page's server and the Foxglove feed, which take the same credentials.
#include <chrono>
#include <cstddef>
#include <map>
#include <mutex>
#include <string>

namespace sarloc::dashboard {

class SessionStore {
 public:
  static constexpr const char* kCookie = "sarloc_session";

  /// `view_token` lets its holder look; `operator_token` lets its holder look and act.
  SessionStore(std::string view_token, std::string operator_token, std::chrono::hours lifetime = std::chrono::hours(12),
               std::size_t max_sessions = 256);

  /// `token` is the view or the operator token (compared in constant time).
  bool may_view(const std::string& token) const;
  bool may_act(const std::string& token) const;
  /// "Bearer TOKEN" with the view or the operator token.
  bool may_view_bearer(const std::string& authorization) const;
  bool may_act_bearer(const std::string& authorization) const;

  /// A new session id (128 random bits, hex); the oldest goes when max_sessions are open.
  std::string open();
  /// The Cookie header holds a session that is open and not expired.
  bool has_session(const std::string& cookie_header) const;
  /// The Set-Cookie value for `session`.
  static std::string set_cookie(const std::string& session, bool secure);

 private:
  std::string view_token_;
  std::string operator_token_;
  std::chrono::hours lifetime_;
  std::size_t max_sessions_;
  mutable std::mutex mutex_;
  std::map<std::string, std::chrono::steady_clock::time_point> sessions_;  // id -> opened
};

/// Constant time in the length of `expected`: a token does not leak through timing.
bool same_secret(const std::string& given, const std::string& expected);

/// A random secret: `bits` random bits as hex.
std::string random_secret(int bits = 128);

}  // namespace sarloc::dashboard
