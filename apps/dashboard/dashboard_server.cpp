#include "dashboard_server.hpp"

#include <arpa/inet.h>
#include <httplib.h>
#include <malloc.h>
#include <netinet/in.h>
#include <spdlog/spdlog.h>
#include <sys/socket.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <regex>
#include <stdexcept>

#include "json_text.hpp"
#include "sarloc/core/common/errors.hpp"
#include "sarloc/core/common/identifier.hpp"
#include "sarloc/core/common/validate.hpp"
#include "sarloc/core/incident/deposit.hpp"
#include "sarloc/core/incident/incident_command.hpp"
#include "tls_context.hpp"

namespace sarloc::dashboard {

namespace {

// The page, embedded at build time (apps/dashboard/page/; CMake writes page_assets.inc).
struct Asset {
  const char* path;
  const char* type;
  const char* body;
};
const Asset kAssets[] = {
#include "page_assets.inc"
};

constexpr std::size_t kMaxHeaderFields = 64;
constexpr std::size_t kDepositPointsMax = incident::IncidentCommandConfig::kDepositVerticesMax;

// A stream's version before its first snapshot.
constexpr std::uint64_t kNothingSent = ~std::uint64_t{0};

void error(httplib::Response& res, int status, const std::string& what) {
  res.status = status;
  res.set_content(json_text(nlohmann::json{{"error", what}}), "application/json");
}

}  // namespace

bool is_loopback_address(const std::string& address) {
  return address == "localhost" || address == "::1" || address.rfind("127.", 0) == 0;
}

void DashboardServerConfig::validate() const {
  if (bind_address.empty()) throw ConfigError("dashboard.bind_address is empty");
  if (port < 0 || port > 65535) throw ConfigError("dashboard.port = " + config_value(port) + ": must be 0-65535");
  if (token.size() < 8) throw ConfigError("dashboard.token: must be at least 8 characters (or absent: a random one is made)");
  if (view_token.size() < 8) throw ConfigError("dashboard.view_token: must be at least 8 characters (or absent: a random one is made)");
  if (view_token == token) throw ConfigError("dashboard.view_token: must differ from dashboard.token (viewers must not act)");
  if (auto problem = identifier_problem(operator_id, "dashboard.operator_id"); !problem.empty()) throw ConfigError(problem);
  if (tls_certificate.empty() != tls_private_key.empty()) {
    throw ConfigError("dashboard.tls_certificate and dashboard.tls_private_key: give both, or neither");
  }
  if (!tls_client_ca.empty() && tls_certificate.empty()) {
    throw ConfigError("dashboard.tls_client_ca = " + tls_client_ca +
                      ": client certificates are asked for in a TLS handshake; give dashboard.tls_certificate and "
                      "dashboard.tls_private_key too");
  }
  if (tls_certificate.empty() && !is_loopback_address(bind_address)) {
    throw ConfigError("dashboard.bind_address = " + bind_address +
                      ": serving beyond this machine needs TLS (dashboard.tls_certificate, dashboard.tls_private_key; "
                      "deploy/security/make-dashboard-cert.sh makes them)");
  }
  const bool wildcard = bind_address == "0.0.0.0" || bind_address == "::";
  if (wildcard && hosts.empty()) {
    throw ConfigError("dashboard.hosts is empty with bind_address " + bind_address +
                      ": list the names and addresses the command post reaches the page by");
  }
  for (const auto& host : hosts) {
    if (host.empty() || host.size() > 253 || host.find_first_of(" /:\t\r\n") != std::string::npos) {
      throw ConfigError("dashboard.hosts: '" + host + "' is not a host name or an IPv4 address");
    }
  }
  if (!(push_period_s >= 0.05 && push_period_s <= 10.0)) {
    throw ConfigError("dashboard.push_period_s = " + config_value(push_period_s) + ": must be in [0.05, 10]");
  }
  if (max_streams < 1 || max_streams > 1000) {
    throw ConfigError("dashboard.max_streams = " + config_value(max_streams) + ": must be 1-1000");
  }
  if (max_connections_per_address < 1 || max_connections_per_address > 1000) {
    throw ConfigError("dashboard.max_connections_per_address = " + config_value(max_connections_per_address) +
                      ": must be 1-1000");
  }
  if (!(request_deadline_s >= 1.0 && request_deadline_s <= 120.0)) {
    throw ConfigError("dashboard.request_deadline_s = " + config_value(request_deadline_s) + ": must be in [1, 120]");
  }
}

DashboardServer::DashboardServer(DashboardServerConfig config, PictureState& state,
                                 std::function<bool(std::uint32_t, const std::string&)> acknowledge)
    : config_(std::move(config)), state_(state), acknowledge_(std::move(acknowledge)) {
  config_.validate();
  // TLS ends in the gate, which holds each decrypted request until it is whole: the server
  // behind it, on loopback, speaks plain HTTP.
  if (tls()) tls_context_ = make_tls_context({config_.tls_certificate, config_.tls_private_key, config_.tls_client_ca});
  server_ = std::make_unique<httplib::Server>();
  sessions_ = std::make_shared<SessionStore>(config_.view_token, config_.token);
  auto& s = *server_;
  // One thread per open stream, and some for everything else.
  const int threads = config_.max_streams + 8;
  s.new_task_queue = [threads] { return new httplib::ThreadPool(static_cast<std::size_t>(threads)); };
  s.set_payload_max_length(kMaxRequestBody);
  s.set_read_timeout(5, 0);
  s.set_write_timeout(5, 0);
  // One request per connection: the gate's deadline then bounds the whole of it.
  s.set_keep_alive_max_count(1);

  // Decided from the request's head, before a byte of its body is read: a chunked body has no
  // Content-Length for the payload limit to refuse it by (a token-less 200 MB chunked POST was
  // read whole before its 401), and 10 000 header fields were accepted.
  s.set_pre_routing_handler([this](const httplib::Request& req, httplib::Response& res) {
    using Outcome = httplib::Server::HandlerResponse;
    // A GET is whole once its head is: it has no deadline any more (an event stream lasts).
    if (req.method == "GET" || req.method == "HEAD") gate_->request_arrived(req.remote_port);
    if (req.headers.size() > kMaxHeaderFields) {
      error(res, 431, "more than " + std::to_string(kMaxHeaderFields) + " header fields");
      return Outcome::Handled;
    }
    if (!known_host(req.get_header_value("Host"))) {
      error(res, 421, "this dashboard is not served under that name (dashboard.hosts)");
      return Outcome::Handled;
    }
    if (req.method == "GET" || req.method == "HEAD") return Outcome::Unhandled;
    // A page of another site may post here from the commander's own browser: its Origin says so.
    // The page's own origin has the scheme it was served with (https behind dashboard.tls_*).
    const std::string origin = req.get_header_value("Origin");
    if (!origin.empty() && origin != (tls() ? "https://" : "http://") + req.get_header_value("Host")) {
      error(res, 403, "a request from another site's page");
      return Outcome::Handled;
    }
    // Signing in and a replay's controls need no operator token (their handlers check theirs).
    if (req.path != "/api/session" && req.path != "/api/replay" && !sessions_->may_act_bearer(req.get_header_value("Authorization"))) {
      error(res, 401, "the operator token is missing or wrong");
      return Outcome::Handled;
    }
    if (req.has_header("Transfer-Encoding")) {
      error(res, 411, "a request body needs a Content-Length (chunked bodies are refused)");
      return Outcome::Handled;
    }
    return Outcome::Unhandled;
  });
  s.set_post_routing_handler([](const httplib::Request&, httplib::Response& res) {
    res.set_header("Content-Security-Policy", "default-src 'self'; img-src 'self' data:; frame-ancestors 'none'; base-uri 'none'");
    res.set_header("X-Frame-Options", "DENY");
    res.set_header("X-Content-Type-Options", "nosniff");
    res.set_header("Referrer-Policy", "no-referrer");
  });

  for (const auto& asset : kAssets) {
    const std::string path = asset.path;
    s.Get(path == "/index.html" ? "/" : path.c_str(), [asset](const httplib::Request&, httplib::Response& res) {
      res.set_content(asset.body, asset.type);
      res.set_header("Cache-Control", "no-store");
    });
  }
  s.Get("/api/session", [this](const httplib::Request& req, httplib::Response& res) {
    // Always 200: the page asks before it signs in, and a 401 would be a console error.
    res.set_content(json_text(nlohmann::json{{"signed_in", may_view(req)},
                                             {"may_act", sessions_->may_act_bearer(req.get_header_value("Authorization"))}}),
                    "application/json");
  });
  s.Post("/api/session", [this](const httplib::Request& req, httplib::Response& res) {
    const nlohmann::json request = nlohmann::json::parse(req.body, nullptr, false);
    if (!request.is_object() || !request.contains("token") || !request["token"].is_string()) {
      return error(res, 400, "expected {\"token\": \"...\"}");
    }
    if (!sessions_->may_view(request["token"].get<std::string>())) return error(res, 401, "the access token is wrong");
    res.set_header("Set-Cookie", SessionStore::set_cookie(sessions_->open(), tls()));
    res.set_content(json_text(nlohmann::json{{"signed_in", true}}), "application/json");
  });
  s.Get("/api/state", [this](const httplib::Request& req, httplib::Response& res) {
    if (!may_view(req)) return error(res, 401, "sign in first: the view token, or a session");
    res.set_content(json_text(state_.snapshot()), "application/json");
  });
  s.Get("/api/geojson", [this](const httplib::Request& req, httplib::Response& res) {
    // For a GIS tool or another agency's map: the view token as a bearer, like /api/state.
    if (!may_view(req)) return error(res, 401, "sign in first: the view token, or a session");
    const auto collection = state_.geojson();
    if (!collection)
      return error(res, 404,
                   "no WGS-84 origin for this incident (the mission's incident: latitude_deg, longitude_deg)");
    res.set_header("Cache-Control", "no-store");
    res.set_content(json_text(*collection), "application/geo+json");
  });
  // A basemap tile (XYZ numbering, as web maps ask): the page places it (the snapshot's "basemap").
  s.Get(R"(/api/basemap/(\d{1,2})/(\d{1,8})/(\d{1,8}))", [this](const httplib::Request& req, httplib::Response& res) {
    if (!may_view(req)) return error(res, 401, "sign in first: the view token, or a session");
    if (!basemap_) return error(res, 404, "no basemap (dashboard.basemap)");
    const auto tile = basemap_->tile(std::stoi(req.matches[1]), std::stol(req.matches[2]), std::stol(req.matches[3]));
    if (!tile) return error(res, 404, "no such tile");
    res.set_header("Cache-Control", "private, max-age=86400");  // the file does not change while we run
    res.set_content(*tile, basemap_->content_type());
  });
  s.Get("/events", [this](const httplib::Request& req, httplib::Response& res) {
    // Checked before a stream is counted: clients without a credential can never use up the
    // streams that the commander's own browser needs.
    if (!may_view(req)) return error(res, 401, "sign in first: the view token, or a session");
    if (streams_.fetch_add(1) >= config_.max_streams) {
      streams_.fetch_sub(1);
      return error(res, 503, "too many open event streams (dashboard.max_streams)");
    }
    res.set_header("Cache-Control", "no-store");
    auto sent = std::make_shared<std::uint64_t>(kNothingSent);
    auto beat = std::make_shared<std::chrono::steady_clock::time_point>();
    res.set_chunked_content_provider(
        "text/event-stream",
        [this, sent, beat](std::size_t, httplib::DataSink& sink) {
          // httplib calls a content provider outside its handler's try: nothing may leave it.
          try {
            return push_events(sink, *sent, *beat);
          } catch (const std::exception& e) {
            spdlog::error("dashboard: an event stream ended on an error: {}", e.what());
            return false;
          }
        },
        [this](bool) {
          // The stream's snapshot was the largest buffer it made: give its memory back now, so
          // that the server's size follows what is open, not what once was.
          if (streams_.fetch_sub(1) == 1) ::malloc_trim(0);
        });
  });
  s.Post(R"(/api/alarms/(\d{1,10})/ack)", [this](const httplib::Request& req, httplib::Response& res) {
    const auto id = std::stoull(req.matches[1]);
    if (id > 0xFFFFFFFFull) return error(res, 400, "no such alarm id");
    const auto alarms = state_.snapshot()["alarms"];
    bool known = false;
    for (const auto& a : alarms) known = known || a["id"].get<std::uint64_t>() == id;
    if (!known) return error(res, 404, "alarm " + std::to_string(id) + " is not in the picture");
    if (!acknowledge_(static_cast<std::uint32_t>(id), config_.operator_id)) return error(res, 503, "DDS refused the acknowledgement");
    state_.note("alarm", "acknowledgement of alarm " + std::to_string(id) + " sent by " + config_.operator_id);
    res.status = 202;
    res.set_content(json_text(nlohmann::json{{"acknowledged", id}, {"operator", config_.operator_id}}), "application/json");
  });
  s.Post(R"(/api/victims/(\d{1,10})/dug-out)", [this](const httplib::Request& req, httplib::Response& res) {
    if (!dug_out_) return error(res, 404, "not live: a replay marks nothing dug out");
    const auto id = std::stoull(req.matches[1]);
    if (id > 0xFFFFFFFFull) return error(res, 400, "no such victim id");
    std::string victim_state;
    const auto victims = state_.snapshot()["victims"];  // a copy: the snapshot is a temporary
    for (const auto& v : victims)
      if (v["id"].get<std::uint64_t>() == id) victim_state = v["state"].get<std::string>();
    if (victim_state.empty()) return error(res, 404, "victim " + std::to_string(id) + " is not in the picture");
    // Incident command refuses it too; saying so here spares the operator a silent no.
    if (victim_state != "FOUND") {
      return error(res, 409,
                   "victim " + std::to_string(id) + " is " + victim_state + ": only a FOUND victim is dug out");
    }
    if (!dug_out_(static_cast<std::uint32_t>(id), config_.operator_id))
      return error(res, 503, "DDS refused the report");
    state_.note("victim", "victim " + std::to_string(id) + " reported dug out by " + config_.operator_id);
    res.status = 202;
    res.set_content(json_text(nlohmann::json{{"dug_out", id}, {"operator", config_.operator_id}}), "application/json");
  });
  s.Post(R"(/api/victims/(\d{1,10})/dig-first)", [this](const httplib::Request& req, httplib::Response& res) {
    if (!dig_order_) return error(res, 404, "not live: a replay changes no dig order");
    const auto id = std::stoull(req.matches[1]);
    if (id > 0xFFFFFFFFull) return error(res, 400, "no such victim id");
    const auto snapshot = state_.snapshot();
    // The operator's victim first, then the order as the page shows it.
    std::vector<std::uint32_t> order{static_cast<std::uint32_t>(id)};
    bool listed = false;
    if (snapshot.contains("plan"))
      for (const auto& d : snapshot["plan"]["digs"]) {
        const auto victim = d["victim"].get<std::uint32_t>();
        if (victim == id)
          listed = true;
        else
          order.push_back(victim);
      }
    if (!listed)
      return error(res, 409, "victim " + std::to_string(id) + " is not in the dig order: only FOUND victims are dug");
    if (!dig_order_(order, config_.operator_id)) return error(res, 503, "DDS refused the dig order");
    state_.note("victim", "dig order: victim " + std::to_string(id) + " first, sent by " + config_.operator_id);
    res.status = 202;
    res.set_content(json_text(nlohmann::json{{"dig_order", order}, {"operator", config_.operator_id}}),
                    "application/json");
  });
  s.Post(R"(/api/teams/([A-Za-z0-9_.\-]{1,64})/par)", [this](const httplib::Request& req, httplib::Response& res) {
    if (!state_.par_reported(req.matches[1], config_.operator_id)) return error(res, 404, "no such team");
    res.set_content(json_text(nlohmann::json{{"par_reported", std::string(req.matches[1])}}), "application/json");
  });
  // An operator's outline of the deposit, drawn on the map: {"outline": [[east, north], ...]}.
  s.Post("/api/deposit", [this](const httplib::Request& req, httplib::Response& res) {
    if (!deposit_) return error(res, 404, "not live: a replay draws no deposit");
    // A cross-site form can post text/plain without asking; application/json it cannot.
    if (req.get_header_value("Content-Type").rfind("application/json", 0) != 0) {
      return error(res, 415, "the body must be application/json");
    }
    std::vector<Eigen::Vector2d> outline;
    try {
      const auto body = nlohmann::json::parse(req.body);
      if (!body.is_object() || !body.contains("outline") || !body["outline"].is_array())
        return error(res, 400, "outline: expected an array of [east, north] points");
      const auto& points = body["outline"];
      if (points.size() > kDepositPointsMax)
        return error(
            res, 400,
            "outline: " + std::to_string(points.size()) + " points; at most " + std::to_string(kDepositPointsMax));
      for (std::size_t i = 0; i < points.size(); ++i) {
        const auto& p = points[i];
        if (!p.is_array() || p.size() != 2 || !p[0].is_number() || !p[1].is_number())
          return error(res, 400, "outline[" + std::to_string(i) + "]: expected [east, north] in metres");
        outline.emplace_back(p[0].get<double>(), p[1].get<double>());
      }
      (void)incident::Deposit(outline, "outline");  // a simple polygon, or a 400 naming why
    } catch (const nlohmann::json::exception&) {
      return error(res, 400, "the body is not JSON");
    } catch (const ConfigError& e) {
      return error(res, 400, e.what());
    }
    if (!deposit_(outline, config_.operator_id)) return error(res, 503, "DDS refused the deposit");
    state_.note("plan",
                "deposit outline of " + std::to_string(outline.size()) + " vertices sent by " + config_.operator_id);
    res.status = 202;
    res.set_content(json_text(nlohmann::json{{"vertices", outline.size()}, {"operator", config_.operator_id}}),
                    "application/json");
  });
  s.Post("/api/replay", [this](const httplib::Request& req, httplib::Response& res) {
    if (!replay_control_) return error(res, 404, "not a replay (sarloc-dashboard --recording)");
    if (!may_view(req)) return error(res, 401, "sign in first: the view token, or a session");
    // A cross-site form can post text/plain without asking; application/json it cannot.
    if (req.get_header_value("Content-Type").rfind("application/json", 0) != 0) {
      return error(res, 415, "the body must be application/json");
    }
    nlohmann::json request;
    try {
      request = nlohmann::json::parse(req.body);
    } catch (const std::exception&) {
      return error(res, 400, "the body is not JSON");
    }
    try {
      res.set_content(json_text(replay_control_(request)), "application/json");
    } catch (const std::invalid_argument& e) {
      error(res, 400, e.what());
    }
  });
  s.set_error_handler([](const httplib::Request&, httplib::Response& res) {
    if (res.body.empty()) res.set_content(json_text(nlohmann::json{{"error", "HTTP " + std::to_string(res.status)}}), "application/json");
  });
  s.set_exception_handler([](const httplib::Request&, httplib::Response& res, std::exception_ptr) {
    error(res, 500, "internal error");  // never a crash
  });
}

DashboardServer::~DashboardServer() { stop(); }

void DashboardServer::set_replay_control(std::function<nlohmann::json(const nlohmann::json&)> control) {
  replay_control_ = std::move(control);
}

void DashboardServer::set_dug_out_action(std::function<bool(std::uint32_t, const std::string&)> dug_out) {
  dug_out_ = std::move(dug_out);
}

void DashboardServer::set_dig_order_action(
    std::function<bool(const std::vector<std::uint32_t>&, const std::string&)> dig_order) {
  dig_order_ = std::move(dig_order);
}

void DashboardServer::set_deposit_action(
    std::function<bool(const std::vector<Eigen::Vector2d>&, const std::string&)> deposit) {
  deposit_ = std::move(deposit);
}

std::shared_ptr<const std::string> DashboardServer::message_for(std::uint64_t since, bool first, std::uint64_t& version) {
  std::lock_guard<std::mutex> lock(cache_mutex_);
  const std::uint64_t now = state_.version();
  auto& cached = cache_[{first, since}];
  if (!cached.text || cached.picture_version != now) {
    const nlohmann::json message = first ? state_.snapshot() : state_.delta(since);
    cached.picture_version = now;
    cached.version = message["version"].get<std::uint64_t>();
    cached.text = std::make_shared<const std::string>("event: " + message["type"].get<std::string>() + "\ndata: " + json_text(message) +
                                                      "\n\n");
  }
  // Old entries (streams long past them) go: the cache holds a few versions, not a history.
  for (auto it = cache_.begin(); it != cache_.end();) {
    it = it->second.picture_version + 64 < now ? cache_.erase(it) : std::next(it);
  }
  version = cached.version;
  return cached.text;
}

bool DashboardServer::push_events(httplib::DataSink& sink, std::uint64_t& sent, std::chrono::steady_clock::time_point& beat) {
  if (stopping_ || !sink.is_writable()) return false;  // the browser left: free the thread
  std::string chunk;
  std::shared_ptr<const std::string> message;
  if (sent == kNothingSent) {
    message = message_for(0, true, sent);
  } else {
    std::this_thread::sleep_for(std::chrono::duration<double>(config_.push_period_s));
    if (stopping_) return false;
    // A delta, or all of it again when the picture was rebuilt (PictureState::delta).
    if (state_.version() > sent) message = message_for(sent, false, sent);
  }
  if (message && !sink.write(message->data(), message->size())) return false;
  const auto now = std::chrono::steady_clock::now();
  if (now - beat >= std::chrono::seconds(1)) {
    beat = now;
    chunk += "event: heartbeat\ndata: " + json_text(state_.heartbeat()) + "\n\n";
  }
  // A closed browser makes the write fail: the provider ends and its thread is free.
  return chunk.empty() || sink.write(chunk.data(), chunk.size());
}

bool DashboardServer::known_host(const std::string& host_header) const {
  std::string host = host_header;
  if (!host.empty() && host.front() == '[') {
    host = host.substr(0, host.find(']') + 1);  // [::1]:8080
  } else if (const auto colon = host.rfind(':'); colon != std::string::npos) {
    host = host.substr(0, colon);
  }
  if (host == "127.0.0.1" || host == "localhost" || host == "[::1]" || host == config_.bind_address) return true;
  return std::find(config_.hosts.begin(), config_.hosts.end(), host) != config_.hosts.end();
}

bool DashboardServer::may_view(const httplib::Request& request) const {
  return sessions_->may_view_bearer(request.get_header_value("Authorization")) ||
         sessions_->has_session(request.get_header_value("Cookie"));
}

namespace {

// Debian's cpp-httplib is a compiled library that listens with a backlog of 5. The gate opens a
// connection to the server for each client at once, so a burst of 50 browsers overflowed it:
// the kernel dropped their handshakes, and each retry waited 1 s or more, eating into the
// gate's request deadline. listen() again on the same socket only widens the queue.
void widen_listen_backlog(int port) {
  for (const auto& entry : std::filesystem::directory_iterator("/proc/self/fd")) {
    int fd = -1;
    try {
      fd = std::stoi(entry.path().filename().string());
    } catch (const std::exception&) {
      continue;
    }
    sockaddr_in address{};
    socklen_t length = sizeof address;
    int listening = 0;
    socklen_t flag_length = sizeof listening;
    if (::getsockname(fd, reinterpret_cast<sockaddr*>(&address), &length) != 0 || address.sin_family != AF_INET ||
        ntohs(address.sin_port) != port || address.sin_addr.s_addr != htonl(INADDR_LOOPBACK)) {
      continue;
    }
    if (::getsockopt(fd, SOL_SOCKET, SO_ACCEPTCONN, &listening, &flag_length) == 0 && listening != 0) ::listen(fd, 1024);
  }
}

}  // namespace

void DashboardServer::start() {
  // One listen per server: a second would leave a joinable thread behind (std::terminate).
  if (stopping_ || thread_.joinable()) throw std::logic_error("DashboardServer::start: already started or stopped");
  const int backend_port = server_->bind_to_any_port("127.0.0.1");
  if (backend_port < 0) throw std::runtime_error("cannot listen on a loopback port for the page's server");
  widen_listen_backlog(backend_port);
  ConnectionLimits limits;
  limits.max_per_address = config_.max_connections_per_address;
  limits.max_total = 4 * (config_.max_streams + 8);
  limits.request_deadline_s = config_.request_deadline_s;
  try {
    gate_ = std::make_unique<ConnectionGate>(limits, config_.bind_address, config_.port, backend_port, tls_context_);
  } catch (const std::runtime_error& e) {
    throw std::runtime_error(std::string(e.what()) + ": address in use, or not this machine's");
  }
  port_ = gate_->port();
  thread_ = std::thread([this] {
    server_->listen_after_bind();
    listen_returned_ = true;
  });
  // cpp-httplib 0.11's stop() does nothing until listen has begun (is_running): a stop right after
  // start left listen running and its join hanging for ever (a CI timeout, 2026-12-07).
  while (!server_->is_running() && !listen_returned_) std::this_thread::sleep_for(std::chrono::milliseconds(1));
}

void DashboardServer::stop() {
  if (stopping_.exchange(true)) return;
  if (gate_) gate_->stop();  // no new connections, and the open ones end: no handler waits on a client
  server_->stop();
  if (thread_.joinable()) thread_.join();
  gate_.reset();  // after the handler threads, which report to it
}

}  // namespace sarloc::dashboard
