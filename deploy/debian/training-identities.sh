#!/usr/bin/env bash
# The shipped training incident's DDS Security material (/etc/sarloc/incident.yaml as shipped,
# dds.security_dir: security): a CA of its own and an identity for each of its nodes, made
# once on this machine by sarloc-common's postinst. A real incident issues its own:
#   make-certs.sh DIR $(sarloc-mission --identities INCIDENT.yaml)   (docs/operations.md, "Security")
# Usage: training-identities.sh ETC_DIR    issues them into ETC_DIR/security unless a CA is there
#        training-identities.sh --list     the identities, one a line (the package check compares
#                                          them with sarloc-mission --identities of the incident)
set -euo pipefail
# = sarloc-mission --identities /etc/sarloc/incident.yaml as shipped.
identities=(core:sarloc-core command:sarloc-command-1 command:sarloc-command-2 device:r1 device:r2
            dashboard:dashboard recorder:recorder recorder:mission)
if [[ "${1:-}" == "--list" ]]; then
  printf '%s\n' "${identities[@]}"
  exit 0
fi
if [[ $# -ne 1 ]]; then
  echo "usage: $0 ETC_DIR | --list" >&2
  exit 64
fi
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
make_certs="$here/make-certs.sh"                                      # installed beside it
[[ -x "$make_certs" ]] || make_certs="$here/../security/make-certs.sh"  # the source tree
out="$1/security"
if [[ -f "$out/ca.pem" ]]; then
  echo "training-identities.sh: $out already has a CA; nothing issued" >&2
  exit 0
fi
umask 077
"$make_certs" "$out" "${identities[@]}" >/dev/null
# The services run as the sarloc group: they read their identities, never the CA's key.
if getent group sarloc >/dev/null 2>&1 && [[ $(id -u) -eq 0 ]]; then
  for spec in "${identities[@]}"; do
    chgrp -R sarloc "$out/${spec#*:}"
    chmod -R g+rX "$out/${spec#*:}"
  done
  chgrp sarloc "$out" "$out/ca.pem" "$out/governance.p7s"
  chmod g+rx "$out"
  chmod g+r "$out/ca.pem" "$out/governance.p7s"
fi
echo "training-identities.sh: ${#identities[@]} training identities in $out"
