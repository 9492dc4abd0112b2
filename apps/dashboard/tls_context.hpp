#pragma once
// The dashboard's TLS, one context for the page (ConnectionGate) and the Foxglove feed: TLS 1.2
// and up, the server's certificate chain and key in PEM, and, when a client authority is given,
// mutual TLS: a client must show a certificate that authority signed (an operator's laptop,
// deploy/security/make-dashboard-client.sh), or its handshake fails. Anyone else on the
// command-post network then costs the dashboard a handshake, never a request (issue 59).
#include <boost/asio/ssl.hpp>
#include <memory>
#include <string>

namespace sarloc::dashboard {

struct TlsFiles {
  std::string certificate;  ///< dashboard.tls_certificate
  std::string private_key;  ///< dashboard.tls_private_key
  std::string client_ca;    ///< dashboard.tls_client_ca; empty: no client certificate is asked for
};

/// Throws ConfigError naming the dashboard keys when a file does not load, the key is not the
/// certificate's, or the client authority holds no certificate.
std::shared_ptr<boost::asio::ssl::context> make_tls_context(const TlsFiles& files);

}  // namespace sarloc::dashboard
