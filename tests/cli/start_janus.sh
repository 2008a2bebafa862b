#!/usr/bin/env bash
# Janus for a test, in the network namespace tests/cli/in_network_namespace.sh made: its
# configuration and log in FOLDER, the VideoRoom plugin and the WebSocket API on 127.0.0.1:8188
# only (and over TLS on 127.0.0.1:8989, its certificate made here for 127.0.0.1 alone, self-signed:
# FOLDER/janus-cert.pem is the authority a client must be told to trust), ICE on ADDRESS (the namespace's own: Janus will not use loopback for media). With
# ADMIN_KEY, rooms are made by the administrator only, as on many real servers.
#   start_janus.sh FOLDER ADDRESS [ADMIN_KEY]      (execs janus: the caller keeps its pid)
set -euo pipefail
folder=$1 address=$2 admin_key=${3:-}
lib=/usr/lib/x86_64-linux-gnu/janus
mkdir -p "$folder"
plugins=$(cd "$lib/plugins" && ls *.so | grep -v '^libjanus_videoroom.so$' | paste -sd, -)
transports=$(cd "$lib/transports" && ls *.so | grep -v '^libjanus_websockets.so$' | paste -sd, -)
cat > "$folder/janus.jcfg" <<CFG
general: {
  configs_folder = "$folder"
  plugins_folder = "$lib/plugins"
  transports_folder = "$lib/transports"
  events_folder = "$lib/events"
  loggers_folder = "$lib/loggers"
  debug_level = 4
  session_timeout = 60
}
media: { rtp_port_range = "20000-20999" }
nat: { ice_enforce_list = "$address" }
plugins: { disable = "$plugins" }
transports: { disable = "$transports" }
events: { broadcast = false }
CFG
openssl req -x509 -newkey rsa:2048 -nodes -days 2 -subj "/CN=127.0.0.1" -addext "subjectAltName=IP:127.0.0.1" \
  -keyout "$folder/janus-key.pem" -out "$folder/janus-cert.pem" 2>/dev/null
cat > "$folder/janus.transport.websockets.jcfg" <<CFG
general: { json = "plain" ws = true ws_port = 8188 ws_ip = "127.0.0.1" wss = true wss_port = 8989 wss_ip = "127.0.0.1" }
admin: { admin_ws = false }
certificates: { cert_pem = "$folder/janus-cert.pem" cert_key = "$folder/janus-key.pem" }
CFG
if [ -n "$admin_key" ]; then
  echo "general: { admin_key = \"$admin_key\" }" > "$folder/janus.plugin.videoroom.jcfg"
else
  echo 'general: { }' > "$folder/janus.plugin.videoroom.jcfg"
fi
exec /usr/bin/janus -F "$folder" -C "$folder/janus.jcfg" -i "$address" -L "$folder/janus.log" -o -N > /dev/null 2>&1
