#!/usr/bin/env bash
# `holovox --demo` as a new user meets it, under Xvfb in a throwaway HOME (no settings, no data):
# the demo study is imported into the study database (the browser's) and opened; the demo
# archive it started is stopped when it quits. With "keep the demo archive running" set, the
# archive outlives the GUI, and a second `holovox --demo` finds it running and leaves it so;
# `holovox-cli demo --stop` ends it. Screenshots kept as test artefacts.
set -euo pipefail
gui=${1:?holovox}; cli=${2:?holovox-cli}
work=$(mktemp -d)
export HOME="$work/home" XDG_CONFIG_HOME="$work/home/.config" XDG_DATA_HOME="$work/home/.local/share"
unset HOLOVOX_DB HOLOVOX_PACS_CONFIG
mkdir -p "$HOME"
cleanup() { "$cli" demo --stop >/dev/null 2>&1 || true; rm -rf "$work"; }
trap cleanup EXIT
art="$(dirname "$gui")/../test-artifacts/gui"
mkdir -p "$art"
demo() {  # runs holovox --demo until its first complete frame, then quits; the log in $work/gui.log
  timeout 280 xvfb-run -a -s "-screen 0 1920x1080x24" "$gui" --demo --screenshot "$1" >"$work/gui.log" 2>&1 ||
    { cat "$work/gui.log"; echo "holovox --demo failed"; exit 1; }
}
studies() {  # the patients of the study database, read by Python's sqlite3, not by Holovox
  /usr/bin/python3 -c "import sqlite3,sys; c=sqlite3.connect(sys.argv[1]); print(' '.join(f'{n}:{k}' for n, k in c.execute(
    'select p.name, count(*) from studies s join patients p on s.patient = p.id group by p.name order by p.name')))" \
    "$XDG_DATA_HOME/holovox/studies.sqlite"
}

demo "$art/demo-first-start.png"
[ "$(studies)" = "HOLOVOX^BRAIN:1" ] || { echo "the demo study is not in the study database: '$(studies)'"; exit 1; }
grep -q "stopped the demo archive" "$work/gui.log" || { cat "$work/gui.log"; echo "quitting did not stop the demo archive"; exit 1; }
# The PACS panel said what the archive was doing: starting, then seeding up to the last image.
grep -q "demo archive: starting Orthanc" "$work/gui.log" || { cat "$work/gui.log"; echo "no starting stage said"; exit 1; }
grep -Eq "demo archive: seeding ([0-9]+) of \1 images" "$work/gui.log" || { cat "$work/gui.log"; echo "seeding was not said to its end"; exit 1; }
if "$cli" demo --status; then echo "the demo archive still runs after quitting"; exit 1; fi

mkdir -p "$XDG_CONFIG_HOME/Holovox"
printf '[demo]\nkeepRunning=true\n' >>"$XDG_CONFIG_HOME/Holovox/Holovox.conf"
demo "$art/demo-kept.png"
"$cli" demo --status || { cat "$work/gui.log"; echo "the demo archive was stopped although kept"; exit 1; }
pid=$(cat "$XDG_DATA_HOME/holovox/demo-archive/orthanc.pid")
printf '[demo]\nkeepRunning=false\n' >"$XDG_CONFIG_HOME/Holovox/Holovox.conf"
demo "$art/demo-found.png"  # found running: not this session's to stop
"$cli" demo --status || { cat "$work/gui.log"; echo "an archive found running was stopped on quit"; exit 1; }
[ "$(cat "$XDG_DATA_HOME/holovox/demo-archive/orthanc.pid")" = "$pid" ] || { echo "the running archive was started again"; exit 1; }
[ "$(studies)" = "HOLOVOX^BRAIN:1" ] || { echo "a second start imported another study: '$(studies)'"; exit 1; }
"$cli" demo --stop
if "$cli" demo --status; then echo "demo --stop left it running"; exit 1; fi

# The archive's port taken by another program: Orthanc is started again, a little later each
# time, and then refused in words that name the port; nothing is left running.
# (On every address and without SO_REUSEADDR, so that Orthanc cannot bind beside it.)
/usr/bin/python3 -c "
import socket, time
for attempt in range(50):  # a port left in TIME_WAIT by the runs above frees within seconds
    try:
        s = socket.socket(); s.bind(('0.0.0.0', 4243)); break
    except OSError:
        s.close(); time.sleep(0.2)
s.listen(1); open('$work/squatting', 'w').close()
time.sleep(90)" &
squatter=$!
for _ in $(seq 100); do [ -e "$work/squatting" ] && break; sleep 0.1; done
[ -e "$work/squatting" ] || { kill $squatter; echo "could not take port 4243 for the test"; exit 1; }
if "$cli" demo >"$work/taken.log" 2>&1; then kill $squatter; cat "$work/taken.log"; echo "the demo started on a taken port"; exit 1; fi
kill $squatter
grep -q "port 4243 or 8043 taken by another program" "$work/taken.log" || { cat "$work/taken.log"; echo "the refusal does not name the port"; exit 1; }
if "$cli" demo --status; then echo "an Orthanc was left running after the refusal"; exit 1; fi
echo "a taken port is refused in words, after three tries"

echo "the demo study is in the browser's database; the archive stops with the GUI unless kept, and is found again"
