#!/usr/bin/env bash
# Creates the DDS Security material for one incident (docs/operations.md, "Security"):
#   OUT/ca.{pem,key}                 the incident's certificate authority (identity + permissions)
#   OUT/governance.p7s               deploy/security/governance.xml signed by the CA (S/MIME)
#   OUT/<node>/{cert.pem,key.pem}    each node's identity (CN=<node>)
#   OUT/<node>/permissions.p7s       what <node> may publish and subscribe, by its role, signed by the CA
#   OUT/<node>/secure.xml            participant profile "sarloc_secure" for <node>: localhost
#                                    transports plus the dds.sec.* properties pointing at the files
# Usage: make-certs.sh OUT [ROLE:]NODE...
#   e.g. make-certs.sh /etc/sarloc/security command:command-1 command:command-2 core:core-west r1 r2
# A node's role decides the topics it may publish (every role may subscribe to every topic):
#   command    the incident picture: incident_frame, fused_victim, team_status, incident_summary,
#              incident_alarm, search_plan (so no other identity can inject a victim, a team or an alarm)
#   core       victim_estimate, guidance, responder_position (map-aided fixes), responder_candidates,
#              rescuer_handover (a responder's estimator handed to another sector's daemon)
#   device     (the default) a rescuer's or firefighter's device: field_measurement, odometry,
#              responder_position, victim_estimate (while its core daemon is unreachable),
#              responder_alarm, victim_recovery (the finder marks a victim dug out)
#   dashboard  alarm_acknowledgement, victim_recovery, dig_order, deposit_drawing
#   recorder   nothing but its node_status
# Every role publishes node_status. Keep OUT/ca.key offline once the nodes are issued.
# Re-running adds nodes with the same CA.
set -euo pipefail
if [[ $# -lt 2 ]]; then
  echo "usage: $0 OUT_DIR [ROLE:]NODE... (ROLE: command, core, device, dashboard, recorder; default device)" >&2
  exit 64
fi
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
out=$(mkdir -p "$1" && cd "$1" && pwd)
shift
# shellcheck source=incident-ca.sh
source "$here/incident-ca.sh"
ensure_incident_ca "$out" make-certs.sh
# The governance: beside this script in the source tree; installed, in the root's
# /etc/sarloc/security (this script is in <root>/usr/share/sarloc/security).
governance="$here/governance.xml"
[[ -f "$governance" ]] || governance="$here/../../../../etc/sarloc/security/governance.xml"
[[ -f "$governance" ]] || { echo "make-certs.sh: no governance.xml beside it or in /etc/sarloc/security" >&2; exit 1; }
openssl smime -sign -text -in "$governance" -out "$out/governance.p7s" \
  -signer "$out/ca.pem" -inkey "$out/ca.key" 2>/dev/null

not_before=$(date -u +%Y-%m-%dT%H:%M:%S)
not_after=$(date -u -d '+10 years' +%Y-%m-%dT%H:%M:%S)
# The topics a role may publish (DDS Security permission topic expressions).
role_topics() {
  case "$1" in
    command) echo "sarloc/incident_frame sarloc/fused_victim sarloc/team_status sarloc/incident_summary sarloc/incident_alarm sarloc/search_plan" ;;
    core) echo "sarloc/victim_estimate sarloc/guidance sarloc/responder_position sarloc/responder_candidates sarloc/rescuer_handover" ;;
    device) echo "sarloc/field_measurement sarloc/odometry sarloc/responder_position sarloc/victim_estimate sarloc/responder_alarm sarloc/victim_recovery" ;;
    dashboard) echo "sarloc/alarm_acknowledgement sarloc/victim_recovery sarloc/dig_order sarloc/deposit_drawing" ;;
    recorder) echo "" ;;
    *) return 1 ;;
  esac
}
for spec in "$@"; do
  if [[ "$spec" == *:* ]]; then role=${spec%%:*}; node=${spec#*:}; else role=device; node=$spec; fi
  if ! role_topics "$role" > /dev/null; then
    echo "make-certs.sh: $spec: unknown role '$role' (command, core, device, dashboard, recorder)" >&2
    exit 64
  fi
  if [[ ! "$node" =~ ^[A-Za-z0-9_.-]{1,64}$ ]]; then
    echo "make-certs.sh: $spec: a node id is 1-64 of A-Z a-z 0-9 _ . -" >&2
    exit 64
  fi
  # Partitions route (sectors: sector-<name>; incident command, the recorder and the Foxglove
  # feed read "*"), topics are the grant: without this list Fast DDS allows only the default
  # partition, and a secured sector daemon or dashboard feed could not create its endpoints.
  partitions="<partitions><partition/><partition>*</partition></partitions>"
  publish="<topic>sarloc/node_status</topic>"
  for topic in $(role_topics "$role"); do publish+="<topic>${topic}</topic>"; done
  dir="$out/$node"
  mkdir -p "$dir"
  openssl ecparam -name prime256v1 -genkey -noout -out "$dir/key.pem" 2>/dev/null
  openssl req -new -sha256 -key "$dir/key.pem" -out "$dir/cert.csr" -subj "/O=sarloc/CN=$node" 2>/dev/null
  openssl x509 -req -sha256 -in "$dir/cert.csr" -CA "$out/ca.pem" -CAkey "$out/ca.key" -CAcreateserial \
    -out "$dir/cert.pem" -days 3650 2>/dev/null
  rm -f "$dir/cert.csr"
  subject=$(openssl x509 -noout -subject -nameopt RFC2253 -in "$dir/cert.pem" | sed 's/^subject=//')
  cat > "$dir/permissions.xml" <<XML
<?xml version="1.0" encoding="UTF-8"?>
<dds xmlns:xsi="http://www.w3.org/2001/XMLSchema-instance"
     xsi:noNamespaceSchemaLocation="http://www.omg.org/spec/DDS-Security/20170801/omg_shared_ca_permissions.xsd">
  <permissions>
    <grant name="${node}_${role}">
      <subject_name>${subject}</subject_name>
      <validity><not_before>${not_before}</not_before><not_after>${not_after}</not_after></validity>
      <allow_rule>
        <domains><id_range><min>0</min><max>232</max></id_range></domains>
        <publish><topics>${publish}</topics>${partitions}</publish>
        <subscribe><topics><topic>sarloc/*</topic></topics>${partitions}</subscribe>
      </allow_rule>
      <default>DENY</default>
    </grant>
  </permissions>
</dds>
XML
  openssl smime -sign -text -in "$dir/permissions.xml" -out "$dir/permissions.p7s" \
    -signer "$out/ca.pem" -inkey "$out/ca.key" 2>/dev/null
  cat > "$dir/secure.xml" <<XML
<?xml version="1.0" encoding="UTF-8" ?>
<!-- sarloc_secure for ${node}: the localhost transports of config/dds/localhost.xml plus DDS
     Security (authentication, access control, encryption). Edit the transports for a field
     network (see config/dds/lan.xml). sarloc checks these settings at start-up and refuses to
     run if one is missing or misspelled. -->
<dds xmlns="http://www.eprosima.com/XMLSchemas/fastRTPS_Profiles">
  <profiles>
    <transport_descriptors>
      <transport_descriptor>
        <transport_id>sarloc_secure_udp4</transport_id>
        <type>UDPv4</type>
        <interfaceWhiteList><address>127.0.0.1</address></interfaceWhiteList>
        <maxInitialPeersRange>32</maxInitialPeersRange>
      </transport_descriptor>
    </transport_descriptors>
    <participant profile_name="sarloc_secure">
      <rtps>
        <name>${node}</name>
        <useBuiltinTransports>false</useBuiltinTransports>
        <userTransports><transport_id>sarloc_secure_udp4</transport_id></userTransports>
        <builtin>
          <metatrafficUnicastLocatorList>
            <locator><udpv4><address>127.0.0.1</address></udpv4></locator>
          </metatrafficUnicastLocatorList>
          <initialPeersList>
            <locator><udpv4><address>127.0.0.1</address></udpv4></locator>
          </initialPeersList>
        </builtin>
        <defaultUnicastLocatorList>
          <locator><udpv4><address>127.0.0.1</address></udpv4></locator>
        </defaultUnicastLocatorList>
        <propertiesPolicy>
          <properties>
            <property><name>dds.sec.auth.plugin</name><value>builtin.PKI-DH</value></property>
            <property><name>dds.sec.auth.builtin.PKI-DH.identity_ca</name><value>file://${out}/ca.pem</value></property>
            <property><name>dds.sec.auth.builtin.PKI-DH.identity_certificate</name><value>file://${dir}/cert.pem</value></property>
            <property><name>dds.sec.auth.builtin.PKI-DH.private_key</name><value>file://${dir}/key.pem</value></property>
            <property><name>dds.sec.access.plugin</name><value>builtin.Access-Permissions</value></property>
            <property><name>dds.sec.access.builtin.Access-Permissions.permissions_ca</name><value>file://${out}/ca.pem</value></property>
            <property><name>dds.sec.access.builtin.Access-Permissions.governance</name><value>file://${out}/governance.p7s</value></property>
            <property><name>dds.sec.access.builtin.Access-Permissions.permissions</name><value>file://${dir}/permissions.p7s</value></property>
            <property><name>dds.sec.crypto.plugin</name><value>builtin.AES-GCM-GMAC</value></property>
          </properties>
        </propertiesPolicy>
      </rtps>
    </participant>
  </profiles>
</dds>
XML
  echo "make-certs.sh: $node ($role) -> $dir/secure.xml"
done
