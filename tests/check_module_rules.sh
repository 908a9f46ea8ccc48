#!/usr/bin/env bash
# The one dependency rule of DESIGN.md: core includes no Qt, GL or DCMTK header; render includes
# no Qt (nor DCMTK); DCMTK headers appear nowhere outside dicom/, and no public dicom/ header
# exposes DCMTK.
set -u
root=${1:?source dir}
fail=0
check() { # dir regex message
  local hits
  hits=$(grep -rnE "$2" "$root/$1" --include='*.h' --include='*.hpp' --include='*.cpp' --include='*.glsl' 2>/dev/null)
  if [ -n "$hits" ]; then echo "RULE BROKEN: $3"; echo "$hits"; fail=1; fi
}
check core '#include *[<"](Q[A-Za-z]*|QtCore/|QtGui/|QtWidgets/|GL/|epoxy/|EGL/|dcmtk/)' "core/ must not include Qt, GL or DCMTK"
check render '#include *[<"](Q[A-Za-z]*|QtCore/|QtGui/|QtWidgets/|dcmtk/)' "render/ must not include Qt or DCMTK"
for d in ui app; do check "$d" '#include *[<"]dcmtk/' "DCMTK stays inside dicom/ ($d/)"; done
hits=$(grep -lE '#include *[<"]dcmtk/' "$root"/dicom/*.h 2>/dev/null)
if [ -n "$hits" ]; then echo "RULE BROKEN: public dicom/ headers expose DCMTK: $hits"; fail=1; fi
# Each module exists as its folder.
for d in app ui core render dicom resources tests installer; do
  [ -d "$root/$d" ] || { echo "missing module folder $d/"; fail=1; }
done
[ $fail -eq 0 ] && echo "module dependency rule holds"
exit $fail
