#!/usr/bin/env bash
# An operator laptop's client certificate for the dashboard (mutual TLS; docs/operations/dashboard.md,
# "Safety"):
#   OUT/dashboard-clients/ca.pem, ca.key       the operators' authority, made on first use and kept:
#                                              dashboard.tls_client_ca is OUT/dashboard-clients/ca.pem
#   OUT/dashboard-clients/NAME/cert.pem, key.pem   NAME's certificate (clientAuth) and key
#   OUT/dashboard-clients/NAME/NAME.p12            both in one file to import in the browser, with
#                                              the password in NAME/p12-password (mode 0600)
# An authority of its own, not the incident CA: every device carries a DDS identity of that one,
# and a lost device must not open the command post's page.
# Usage: make-dashboard-client.sh OUT NAME   e.g. make-dashboard-client.sh /etc/sarloc/security commander-laptop
# NAME: letters, digits, '.', '_' and '-'. Keep OUT/dashboard-clients/ca.key offline.
set -euo pipefail
if [[ $# -ne 2 ]]; then
  echo "usage: $0 OUT_DIR NAME" >&2
  exit 64
fi
if [[ ! "$2" =~ ^[A-Za-z0-9._-]{1,64}$ || "$2" == .* ]]; then
  echo "$0: NAME '$2': use 1-64 letters, digits, '.', '_' or '-', not starting with '.'" >&2
  exit 64
fi
command -v openssl >/dev/null || { echo "make-dashboard-client.sh: openssl is needed (apt-get install openssl)" >&2; exit 1; }
out=$(mkdir -p "$1" && cd "$1" && pwd)
name=$2
umask 077
authority="$out/dashboard-clients"
mkdir -p "$authority"
if [[ ! -f "$authority/ca.pem" ]]; then
  openssl ecparam -name prime256v1 -genkey -noout -out "$authority/ca.key" 2>/dev/null
  openssl req -new -x509 -sha256 -key "$authority/ca.key" -out "$authority/ca.pem" -days 3650 \
    -subj "/O=sarloc/CN=sarloc dashboard operators CA" 2>/dev/null
  chmod 0644 "$authority/ca.pem"
fi
dir="$authority/$name"
mkdir -p "$dir"
openssl ecparam -name prime256v1 -genkey -noout -out "$dir/key.pem" 2>/dev/null
openssl req -new -sha256 -key "$dir/key.pem" -out "$dir/cert.csr" -subj "/O=sarloc/CN=$name" 2>/dev/null
printf 'extendedKeyUsage=clientAuth\nkeyUsage=digitalSignature\n' > "$dir/extensions.cnf"
openssl x509 -req -sha256 -in "$dir/cert.csr" -CA "$authority/ca.pem" -CAkey "$authority/ca.key" -CAcreateserial \
  -out "$dir/cert.pem" -days 825 -extfile "$dir/extensions.cnf" 2>/dev/null
rm -f "$dir/cert.csr" "$dir/extensions.cnf"
openssl rand -hex 12 > "$dir/p12-password"
openssl pkcs12 -export -in "$dir/cert.pem" -inkey "$dir/key.pem" -name "sarloc dashboard: $name" \
  -out "$dir/$name.p12" -passout "file:$dir/p12-password" 2>/dev/null
echo "make-dashboard-client.sh: $dir/$name.p12 (password in $dir/p12-password); dashboard.tls_client_ca: $authority/ca.pem"
