#!/usr/bin/env bash
# PACS benchmark against real peers on loopback, each tool measured in the same run as its
# peer-tool baseline (a benchmark, not a test):
#   - Orthanc 1.10 with its DICOMweb plugin: a 500-instance 256x256 CT series by C-GET
#     (getscu vs holovox), C-MOVE (movescu vs holovox), C-STORE (storescu vs holovox) and
#     WADO-RS (curl of the same multipart URL vs holovox, and curl plus copying and flushing the
#     same 500 files, which Holovox must store as files); a 5-series study (5 x 100) by C-GET
#     with one association and with three at once;
#   - dcmqrscp: the same series by C-GET (getscu vs holovox).
# Prints instances/s and MB/s per row and the ratios. The WADO-RS rows, a fraction of a second
# each and at the mercy of the disk's flushes, are the median of --repeat runs (default 7), the
# three kinds alternating.
#
#   bash tests/bench/bench_pacs.sh [--cli PATH] [--instances 500] [--repeat 7] [--only store|get|move|wado|study|dcmqrscp]
#        [--receive-in DIR]  (what the retrieves receive, and their database, go to a fresh folder in DIR,
#                             for a file system other than the temporary folder's: a journal makes flushes dearer)
set -euo pipefail
cli=build/release/app/holovox-cli
count=500
repeat=7
only=
receiveIn=
while [ $# -gt 0 ]; do
  case $1 in --cli) cli=$2; shift 2 ;; --instances) count=$2; shift 2 ;; --only) only=$2; shift 2 ;; --repeat) repeat=$2; shift 2 ;; --receive-in) receiveIn=$2; shift 2 ;; *) echo "unknown option $1" >&2; exit 2 ;; esac
done
[ -x "$cli" ] || { echo "build first: cmake --workflow --preset release (or pass --cli)" >&2; exit 2; }
cli=$(realpath "$cli")
work=$(mktemp -d)
recv=$work
[ -z "$receiveIn" ] || recv=$(mktemp -d -p "$receiveIn")
cleanup() {
  for f in "$work"/*.pid; do [ -f "$f" ] && kill "$(cat "$f")" 2>/dev/null || true; done
  rm -rf "$work" "$recv"
}
trap cleanup EXIT
port=$((20000 + RANDOM % 20000)); http=$((port + 1)); scp=$((port + 2)); qr=$((port + 3))
mkdir -p "$work/storage" "$work/qr"
cat > "$work/orthanc.json" <<JSON
{ "Name": "bench", "StorageDirectory": "$work/storage", "IndexDirectory": "$work/storage", "HttpPort": $http,
  "DicomPort": $port, "DicomAet": "ORTHANC", "RemoteAccessAllowed": false, "AuthenticationEnabled": false,
  "DicomAlwaysAllowEcho": true, "DicomAlwaysAllowStore": true, "DicomCheckModalityHost": false,
  "StorageCompression": false, "Plugins": ["/usr/share/orthanc/plugins/libOrthancDicomWeb.so"],
  "DicomWeb": { "Enable": true, "Root": "/dicom-web/" },
  "DicomModalities": { "holovox": ["HOLOVOX", "127.0.0.1", $scp], "movescu": ["MOVESCU", "127.0.0.1", $scp] } }
JSON
Orthanc "$work/orthanc.json" >"$work/orthanc.log" 2>&1 & echo $! > "$work/orthanc.pid"
cat > "$work/dcmqrscp.cfg" <<CFG
NetworkTCPPort = $qr
MaxPDUSize = 116794
MaxAssociations = 16
HostTable BEGIN
holovox = (HOLOVOX, 127.0.0.1, $scp)
HostTable END
VendorTable BEGIN
VendorTable END
AETable BEGIN
DCMQR $work/qr RW (2000, 4096mb) ANY
AETable END
CFG
dcmqrscp -c "$work/dcmqrscp.cfg" --disable-host-lookup >"$work/dcmqrscp.log" 2>&1 & echo $! > "$work/dcmqrscp.pid"
for p in $port $http $qr; do
  for i in $(seq 1 150); do (echo > /dev/tcp/127.0.0.1/$p) 2>/dev/null && break; sleep 0.1; done
done
"$cli" export-dicom "phantom:256x256x$count" -o "$work/series" --patient "BENCH^PACS" >/dev/null
study=$(dcmdump "$work/series/IMG00001.dcm" | sed -n 's/.*(0020,000d) UI \[\(.*\)\].*/\1/p')
series=$(dcmdump "$work/series/IMG00001.dcm" | sed -n 's/.*(0020,000e) UI \[\(.*\)\].*/\1/p')
bytes=$(du -sb "$work/series" | cut -f1)
# A study of five 100-instance series (one study UID).
study5="1.2.826.0.1.3680043.9.7777.$RANDOM$RANDOM"
for s in 1 2 3 4 5; do
  "$cli" export-dicom "phantom:256x256x100" -o "$work/study5/s$s" --patient "BENCH^FIVE" --series "series $s" >/dev/null
  dcmodify -nb -q -m "(0020,000d)=$study5" "$work"/study5/s$s/*.dcm
done
bytes5=$(du -sb "$work/study5" | cut -f1)

export HOLOVOX_PACS_CONFIG="$work/pacs.json" HOLOVOX_DB="$recv/db.sqlite"
"$cli" pacs add bench --ae ORTHANC --host 127.0.0.1 --port $port --local-port $scp --storage "$recv/rx" >/dev/null
"$cli" pacs add web --dicomweb "http://127.0.0.1:$http/dicom-web" >/dev/null
"$cli" pacs add qr --ae DCMQR --host 127.0.0.1 --port $qr >/dev/null
t() { local s e; s=$(date +%s.%N); "$@" >"$work/last.log" 2>&1 || { cat "$work/last.log" >&2; exit 1; }; e=$(date +%s.%N); echo "$e - $s" | bc -l; }
row() { printf '  %-40s %7.3f s  %7.1f inst/s  %6.1f MB/s\n' "$1" "$2" "$(echo "$3 / $2" | bc -l)" "$(echo "$4 / 1000000 / $2" | bc -l)"; }
ratio() { printf '  %-40s %.2fx\n' "$1" "$(echo "$2 / $3" | bc -l)"; }
want() { [ -z "$only" ] || [ "$only" = "$1" ]; }
fresh() { rm -rf "$recv/rx" "$recv/db.sqlite"* "$recv/g"; mkdir -p "$recv/g"; }

if want store; then
  echo "C-STORE of $count instances ($(echo "$bytes/1000000" | bc) MB) to Orthanc on loopback:"
  s1=$(t storescu -aet SEEDER -aec ORTHANC 127.0.0.1 $port "$work"/series/*.dcm)
  row "storescu" "$s1" $count $bytes
  for id in $(curl -s "http://127.0.0.1:$http/studies" | tr -d '[]", ' | tr '\n' ' '); do curl -s -X DELETE "http://127.0.0.1:$http/studies/$id" >/dev/null; done
  s2=$(t "$cli" pacs send bench "$work"/series/*.dcm)
  row "holovox pacs send (3 associations)" "$s2" $count $bytes
  ratio "holovox / storescu throughput" "$s1" "$s2"
else
  "$cli" pacs send bench "$work"/series/*.dcm >/dev/null
fi
want study && storescu -aet SEEDER -aec ORTHANC 127.0.0.1 $port "$work"/study5/s*/*.dcm >/dev/null
want dcmqrscp && storescu -aet SEEDER -aec DCMQR 127.0.0.1 $qr "$work"/series/*.dcm >/dev/null

want get || want move || want wado && echo "retrieve of the same series from Orthanc:"
if want get; then
  fresh; g1=$(t getscu -S -aet HOLOVOX -aec ORTHANC -k QueryRetrieveLevel=SERIES -k StudyInstanceUID=$study -k SeriesInstanceUID=$series -od "$recv/g" 127.0.0.1 $port)
  row "getscu (C-GET)" "$g1" $count $bytes
  fresh; g2=$(TCP_NODELAY=1 t getscu -S -aet HOLOVOX -aec ORTHANC -k QueryRetrieveLevel=SERIES -k StudyInstanceUID=$study -k SeriesInstanceUID=$series -od "$recv/g" 127.0.0.1 $port)
  row "getscu with TCP_NODELAY=1 in its env" "$g2" $count $bytes
  fresh; h1=$(t "$cli" pacs get bench $study --no-build)
  row "holovox pacs get (C-GET)" "$h1" $count $bytes
  ratio "holovox / getscu throughput" "$g1" "$h1"
fi
if want move; then
  fresh; m1=$(t movescu -S -aet MOVESCU -aec ORTHANC -aem MOVESCU --port $scp -k QueryRetrieveLevel=SERIES -k StudyInstanceUID=$study -k SeriesInstanceUID=$series -od "$recv/g" 127.0.0.1 $port)
  row "movescu (C-MOVE, own SCP)" "$m1" $count $bytes
  fresh; h2=$(t "$cli" pacs move bench $study --no-build)
  row "holovox pacs move (C-MOVE)" "$h2" $count $bytes
  ratio "holovox / movescu throughput" "$m1" "$h2"
fi
if want wado; then
  # The plain cost of what Holovox must do besides the transfer: store the instances as 500
  # files, flushed (curl writes one file, unflushed).
  c=(); w=(); k=()
  for r in $(seq 1 "$repeat"); do
    fresh; c+=("$(t curl -s -o "$recv/g/all.multipart" -H 'Accept: multipart/related; type="application/dicom"; transfer-syntax=*' "http://127.0.0.1:$http/dicom-web/studies/$study/series/$series")")
    multipart=$(stat -c %s "$recv/g/all.multipart")
    fresh; w+=("$(t "$cli" pacs get web $study --no-build)")
    fresh; k+=("$(t sh -c "cp -r '$work/series' '$recv/g/copy' && sync -f '$recv/g/copy/IMG00001.dcm'")")
  done
  median() { printf '%s\n' "$@" | sort -g | awk '{v[NR] = $1} END {print v[int((NR + 1) / 2)]}'; }
  c1=$(median "${c[@]}"); w1=$(median "${w[@]}"); k1=$(median "${k[@]}")
  echo "  (median of $repeat runs each, alternating)"
  row "curl of the WADO-RS multipart URL" "$c1" $count "$multipart"
  row "holovox pacs get (WADO-RS)" "$w1" $count $bytes
  ratio "holovox / curl time (target <= 1.2)" "$w1" "$c1"
  row "cp of the 500 files + syncfs" "$k1" $count $bytes
  ratio "holovox / (curl + cp + syncfs) time" "$w1" "$(echo "$c1 + $k1" | bc -l)"
fi

if want study; then
  echo "a study of 5 series x 100 instances ($(echo "$bytes5/1000000" | bc) MB) from Orthanc by C-GET:"
  fresh; p1=$(t "$cli" pacs get bench $study5 --no-build --parallel 1)
  row "holovox, one association at a time" "$p1" 500 $bytes5
  fresh; p3=$(t "$cli" pacs get bench $study5 --no-build --parallel 3)
  row "holovox, three associations at once" "$p3" 500 $bytes5
  ratio "speed-up of three associations" "$p1" "$p3"
fi

if want dcmqrscp; then
  echo "retrieve of the same series from dcmqrscp:"
  fresh; q1=$(t getscu -S -aet HOLOVOX -aec DCMQR -k QueryRetrieveLevel=SERIES -k StudyInstanceUID=$study -k SeriesInstanceUID=$series -od "$recv/g" 127.0.0.1 $qr)
  row "getscu (C-GET)" "$q1" $count $bytes
  fresh; q2=$(t "$cli" pacs get qr $study --no-build)
  row "holovox pacs get (C-GET)" "$q2" $count $bytes
  ratio "holovox / getscu throughput" "$q1" "$q2"
fi
