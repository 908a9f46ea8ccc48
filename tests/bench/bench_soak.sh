#!/usr/bin/env bash
# Bounded soak of the storage receiver (a benchmark, not a test): four senders push 2,000
# instances in all into `holovox-cli listen` at once, while a C-GET retrieve from an Orthanc runs
# into the same database and a render orbits a volume. Reports instances stored and lost (must
# be 0), the receiver's peak memory and the slowest association, next to the same four senders
# pushing into DCMTK's storescp in the same run (the baseline).
#
#   bash tests/bench/bench_soak.sh [--cli PATH] [--instances 2000]
set -euo pipefail
cli=build/ci/app/holovox-cli
count=2000
while [ $# -gt 0 ]; do
  case $1 in --cli) cli=$2; shift 2 ;; --instances) count=$2; shift 2 ;; *) echo "unknown option $1" >&2; exit 2 ;; esac
done
[ -x "$cli" ] || { echo "build first: cmake --workflow --preset ci (or pass --cli)" >&2; exit 2; }
work=$(mktemp -d)
pids=()
trap 'for p in "${pids[@]}"; do kill "$p" 2>/dev/null || true; done; [ -n "${KEEP:-}" ] || rm -rf "$work"' EXIT
export HOME="$work/home" XDG_CONFIG_HOME="$work/home/.config" XDG_DATA_HOME="$work/home/.local/share"
export HOLOVOX_PACS_CONFIG="$work/pacs.json" HOLOVOX_DB="$work/db.sqlite"
mkdir -p "$HOME"
port=$((20000 + RANDOM % 20000)); http=$((port + 1)); scp=$((port + 2)); base=$((port + 3))
peak() { awk '/^VmHWM/ {print $2}' "/proc/$1/status"; }  # a process's peak RSS, KiB
up() { for _ in $(seq 1 100); do (echo > "/dev/tcp/127.0.0.1/$1") 2>/dev/null && return 0; sleep 0.1; done; return 1; }

per=$((count / 4))
for s in 1 2 3 4; do  # four patients, one series each
  "$cli" export-dicom "phantom:128x128x$per" -o "$work/send$s" --patient "SOAK^SENDER$s" >/dev/null
done
"$cli" export-dicom "phantom:256x256x200" -o "$work/pacs" --patient "SOAK^RETRIEVE" >/dev/null
"$cli" phantom --size 128x128x128 -o "$work/orbit.hvo" --quiet
cat > "$work/orthanc.json" <<JSON
{ "Name": "soak", "StorageDirectory": "$work/orthanc", "IndexDirectory": "$work/orthanc", "HttpPort": $http,
  "DicomPort": $port, "DicomAet": "ORTHANC", "RemoteAccessAllowed": false, "AuthenticationEnabled": false,
  "DicomAlwaysAllowEcho": true, "DicomAlwaysAllowStore": true, "DicomCheckModalityHost": false, "Plugins": [],
  "DicomModalities": { "holovox": ["HOLOVOX", "127.0.0.1", $scp] } }
JSON
Orthanc "$work/orthanc.json" >"$work/orthanc.log" 2>&1 & pids+=($!)
up "$port"
storescu -aet SEEDER -aec ORTHANC 127.0.0.1 "$port" "$work"/pacs/*.dcm
study=$(dcmdump "$work/pacs/IMG00001.dcm" | sed -n 's/.*(0020,000d) UI \[\(.*\)\].*/\1/p')
"$cli" pacs add soak --ae ORTHANC --host 127.0.0.1 --port "$port" --local-port "$scp" --storage "$work/rx" >/dev/null
for s in 1 2 3 4; do  # the senders are nodes of the table: the receiver accepts them from loopback only
  "$cli" pacs add "modality$s" --ae "MODALITY$s" --host 127.0.0.1 --port 104 >/dev/null
done

# Four senders at once; each association's wall time.
push() {  # label port
  local s senders=()
  for s in 1 2 3 4; do
    ( set +e; a=$(date +%s.%N); storescu -aet MODALITY$s -aec "$1" 127.0.0.1 "$2" "$work"/send$s/*.dcm \
        >"$work/$1.$s.log" 2>&1; rc=$?; echo "$rc $(echo "$(date +%s.%N) - $a" | bc -l)" >"$work/$1.$s.time" ) &
    senders+=($!)
  done
  wait "${senders[@]}"
}
report() {  # label stored rss_kib push-label
  local slowest=0 failed=0 s rc t
  for s in 1 2 3 4; do
    read -r rc t <"$work/$4.$s.time"
    [ "$rc" = 0 ] || { failed=$((failed + 1)); tail -3 "$work/$4.$s.log" >&2; }
    slowest=$(echo "if ($t > $slowest) $t else $slowest" | bc -l)
  done
  printf '  %-28s stored %5d  lost %4d  senders failed %d  slowest association %6.2f s  peak RSS %6.1f MiB\n' \
    "$1" "$2" "$((count - $2))" "$failed" "$slowest" "$(echo "$3 / 1024" | bc -l)"
}
echo "soak: 4 senders x $per instances (128x128) at once:"

# Baselines: DCMTK's storescp as it runs by default (one association at a time: the other
# senders wait, and time out), and with --fork (a process per association: the fair peer for
# concurrent senders; its peak RSS is the listening parent's only), nothing else running.
baseline() {  # label push-label [storescp options]
  local label=$1 tag=$2; shift 2
  mkdir -p "$work/$tag"
  storescp "$@" -aet "$tag" -od "$work/$tag" "$base" & pids+=($!)
  up "$base"
  push "$tag" "$base"
  sleep 1  # forked children finish writing
  rss=$(peak "${pids[-1]}"); kill "${pids[-1]}"; wait "${pids[-1]}" 2>/dev/null || true
  report "$label" "$(find "$work/$tag" -type f | wc -l)" "$rss" "$tag"
}
baseline "storescp (default, alone)" STORESCP
baseline "storescp --fork (alone)" FORKSCP --fork

# Holovox's receiver, with a retrieve and an orbiting render at the same time.
"$cli" listen --port "$base" --storage "$work/pushed" >"$work/listen.log" 2>&1 & pids+=($!)
listener=${pids[-1]}
up "$base"
( "$cli" pacs get soak "$study" >"$work/retrieve.log" 2>&1; echo $? >"$work/retrieve.rc" ) &
retrieve=$!
( for az in $(seq 0 30 330); do "$cli" render "$work/orbit.hvo" --view "$az,20,1" --size 256x256 -o "$work/orbit.png" >/dev/null 2>&1 || true; done ) &
orbit=$!
push HOLOVOX "$base"
wait "$retrieve" "$orbit"
rss=$(peak "$listener"); kill -INT "$listener"; wait "$listener" 2>/dev/null || true
stored=$(grep -c '^received ' "$work/listen.log" || true)
report "holovox-cli listen (loaded)" "$stored" "$rss" HOLOVOX
indexed=$(sqlite3 "$HOLOVOX_DB" "SELECT count(*) FROM instances;")
echo "  database: $indexed instances indexed ($count pushed + 200 retrieved expected); retrieve exit $(cat "$work/retrieve.rc")"
