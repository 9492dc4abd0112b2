#include "tls_context.hpp"

#include <openssl/ssl.h>

#include "sarloc/core/common/errors.hpp"

namespace sarloc::dashboard {

namespace ssl = boost::asio::ssl;

std::shared_ptr<ssl::context> make_tls_context(const TlsFiles& files) {
  const std::string keys =
      "dashboard.tls_certificate = " + files.certificate + ", dashboard.tls_private_key = " + files.private_key;
  auto context = std::make_shared<ssl::context>(ssl::context::tls_server);
  try {
    context->set_options(ssl::context::default_workarounds | ssl::context::no_sslv2 | ssl::context::no_sslv3 |
                         ssl::context::no_tlsv1 | ssl::context::no_tlsv1_1 | ssl::context::single_dh_use);
    context->use_certificate_chain_file(files.certificate);
    context->use_private_key_file(files.private_key, ssl::context::pem);
  } catch (const boost::system::system_error& e) {
    throw ConfigError(keys + ": not a certificate and its key in PEM (or unreadable): " + e.what());
  }
  if (SSL_CTX_check_private_key(context->native_handle()) != 1) {
    throw ConfigError(keys + ": the key is not the certificate's");
  }
  if (files.client_ca.empty()) return context;
  boost::system::error_code ec;
  context->load_verify_file(files.client_ca, ec);
  if (ec) {
    throw ConfigError("dashboard.tls_client_ca = " + files.client_ca +
                      ": not an authority's certificate in PEM (or unreadable): " + ec.message());
  }
  // The authorities a client may choose its certificate from (a browser lists only these).
  STACK_OF(X509_NAME)* names = SSL_load_client_CA_file(files.client_ca.c_str());
  if (names == nullptr) {
    throw ConfigError("dashboard.tls_client_ca = " + files.client_ca + ": holds no certificate");
  }
  SSL_CTX_set_client_CA_list(context->native_handle(), names);
  context->set_verify_mode(ssl::verify_peer | ssl::verify_fail_if_no_peer_cert);
  return context;
}

}  // namespace sarloc::dashboard
