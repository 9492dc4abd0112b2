# Sourced by make-certs.sh and make-dashboard-cert.sh: one incident certificate authority in
# OUT (ca.pem, ca.key), made on first use and kept, so that DDS identities and the dashboard's
# TLS certificate are signed by the same CA.
#   ensure_incident_ca OUT_DIR CALLER_NAME
ensure_incident_ca() {
  command -v openssl >/dev/null || { echo "$2: openssl is needed (apt-get install openssl)" >&2; exit 1; }
  if [[ ! -f "$1/ca.pem" ]]; then
    openssl ecparam -name prime256v1 -genkey -noout -out "$1/ca.key" 2>/dev/null
    openssl req -new -x509 -sha256 -key "$1/ca.key" -out "$1/ca.pem" -days 3650 \
      -subj "/O=sarloc/CN=sarloc incident CA" 2>/dev/null
  fi
}
