#!/usr/bin/env bash
# Retrieve benchmark against a real Orthanc on loopback (started here with a throwaway
# configuration), side by side with DCMTK's getscu and movescu in the same run:
#   - a 500-instance 256x256 CT series by C-GET and by C-MOVE: instances/s and MB/s;
#   - time from the start of the retrieve to a built octree, against retrieve-then-build.
#
#   bash tests/bench/bench_pacs.sh [--cli PATH] [--instances 500]
set -euo pipefail
cli=build/release/app/holovox-cli
count=500
while [ $# -gt 0 ]; do
  case $1 in --cli) cli=$2; shift 2 ;; --instances) count=$2; shift 2 ;; *) echo "unknown option $1" >&2; exit 2 ;; esac
done
[ -x "$cli" ] || { echo "build first: cmake --workflow --preset release (or pass --cli)" >&2; exit 2; }
work=$(mktemp -d)
trap 'kill $(cat "$work/orthanc.pid" 2>/dev/null) 2>/dev/null || true; rm -rf "$work"' EXIT
port=$((20000 + RANDOM % 20000)); http=$((port + 1)); scp=$((port + 2))
cat > "$work/orthanc.json" <<JSON
{ "Name": "bench", "StorageDirectory": "$work/storage", "IndexDirectory": "$work/storage", "HttpPort": $http,
  "DicomPort": $port, "DicomAet": "ORTHANC", "RemoteAccessAllowed": false, "AuthenticationEnabled": false,
  "DicomAlwaysAllowEcho": true, "DicomAlwaysAllowStore": true, "DicomCheckModalityHost": false, "Plugins": [],
  "DicomModalities": { "holovox": ["HOLOVOX", "127.0.0.1", $scp], "movescu": ["MOVESCU", "127.0.0.1", $scp] } }
JSON
Orthanc "$work/orthanc.json" >"$work/orthanc.log" 2>&1 & echo $! > "$work/orthanc.pid"
for i in $(seq 1 100); do (echo > /dev/tcp/127.0.0.1/$port) 2>/dev/null && break; sleep 0.1; done
"$cli" export-dicom "phantom:256x256x$count" -o "$work/series" --patient "BENCH^PACS" >/dev/null
storescu -aet SEEDER -aec ORTHANC 127.0.0.1 $port "$work"/series/*.dcm
study=$(dcmdump "$work/series/IMG00001.dcm" | sed -n 's/.*(0020,000d) UI \[\(.*\)\].*/\1/p')
bytes=$(du -sb "$work/series" | cut -f1)
export HOLOVOX_PACS_CONFIG="$work/pacs.json" HOLOVOX_DB="$work/db.sqlite"
"$cli" pacs add bench --ae ORTHANC --host 127.0.0.1 --port $port --local-port $scp --storage "$work/rx" >/dev/null
t() { local s e; s=$(date +%s.%N); "$@" >"$work/last.log" 2>&1; e=$(date +%s.%N); echo "$e - $s" | bc -l; }
row() { printf '  %-34s %7.2f s  %7.1f inst/s  %6.1f MB/s\n' "$1" "$2" "$(echo "$count / $2" | bc -l)" "$(echo "$bytes / 1000000 / $2" | bc -l)"; }
echo "retrieve of $count instances ($(echo "$bytes/1000000" | bc) MB) from Orthanc on loopback:"
rm -rf "$work/g"; mkdir -p "$work/g"
g1=$(t getscu -aet HOLOVOX -aec ORTHANC -k QueryRetrieveLevel=STUDY -k StudyInstanceUID=$study -od "$work/g" 127.0.0.1 $port)
row "getscu (C-GET)" "$g1"
rm -rf "$work/rx" "$work/db.sqlite"*
h1=$(t "$cli" pacs get bench $study --no-build)
row "holovox pacs get (C-GET)" "$h1"
printf '  ratio holovox/getscu throughput    %.2f (target >= 0.9)\n' "$(echo "$g1 / $h1" | bc -l)"
rm -rf "$work/m"; mkdir -p "$work/m"
m1=$(t movescu -aet MOVESCU -aec ORTHANC -aem MOVESCU --port $scp -k QueryRetrieveLevel=STUDY -k StudyInstanceUID=$study -od "$work/m" 127.0.0.1 $port)
row "movescu (C-MOVE, own SCP)" "$m1"
rm -rf "$work/rx" "$work/db.sqlite"*
h2=$(t "$cli" pacs move bench $study --no-build)
row "holovox pacs move (C-MOVE)" "$h2"
printf '  ratio holovox/movescu throughput   %.2f\n' "$(echo "$m1 / $h2" | bc -l)"
rm -rf "$work/rx" "$work/db.sqlite"* "$work/octrees"
b1=$(t "$cli" pacs get bench $study)
series=$(ls "$work/rx"/*/ | head -1)
echo "time to a built octree:"
printf '  %-34s %7.2f s\n' "holovox pacs get + build" "$b1"
printf '  %-34s %7.2f s (get %.2f s, then build)\n' "retrieve, then import --build" "$(echo "$h1 + $(t "$cli" import "$work/rx" --db "$work/db2.sqlite" --build)" | bc -l)" "$h1"
