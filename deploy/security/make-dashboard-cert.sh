#!/usr/bin/env bash
# The dashboard's TLS certificate for the command post (docs/operations/dashboard.md, "Safety"):
#   OUT/dashboard-tls/cert.pem, key.pem   valid for every HOST given (names or IP addresses),
#                                         signed by the incident CA OUT/ca.pem (made by
#                                         make-certs.sh, or here when there is none yet)
# Usage: make-dashboard-cert.sh OUT HOST...   e.g. make-dashboard-cert.sh /etc/sarloc/security post-1.local 10.0.0.5
# Then, in the mission file: dashboard: {bind_address: 0.0.0.0, tls_certificate: OUT/dashboard-tls/cert.pem,
# tls_private_key: OUT/dashboard-tls/key.pem}. Browsers trust the page once OUT/ca.pem is imported
# as an authority on the command post's laptops. Keep OUT/ca.key offline.
set -euo pipefail
if [[ $# -lt 2 ]]; then
  echo "usage: $0 OUT_DIR HOST..." >&2
  exit 64
fi
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
out=$(mkdir -p "$1" && cd "$1" && pwd)
shift
# shellcheck source=incident-ca.sh
source "$here/incident-ca.sh"
ensure_incident_ca "$out" make-dashboard-cert.sh
names=""
for host in "$@"; do
  if [[ "$host" =~ ^[0-9.]+$ || "$host" == *:* ]]; then names+="IP:$host,"; else names+="DNS:$host,"; fi
done
dir="$out/dashboard-tls"
mkdir -p "$dir"
umask 077
openssl ecparam -name prime256v1 -genkey -noout -out "$dir/key.pem" 2>/dev/null
openssl req -new -sha256 -key "$dir/key.pem" -out "$dir/cert.csr" -subj "/O=sarloc/CN=$1" 2>/dev/null
printf 'subjectAltName=%s\nextendedKeyUsage=serverAuth\n' "${names%,}" > "$dir/extensions.cnf"
openssl x509 -req -sha256 -in "$dir/cert.csr" -CA "$out/ca.pem" -CAkey "$out/ca.key" -CAcreateserial \
  -out "$dir/cert.pem" -days 825 -extfile "$dir/extensions.cnf" 2>/dev/null
rm -f "$dir/cert.csr" "$dir/extensions.cnf"
echo "make-dashboard-cert.sh: $dir/cert.pem for ${names%,}"
