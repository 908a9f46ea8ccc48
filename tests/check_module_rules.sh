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
# core's rooms (DESIGN.md "core's rooms"): each sub-folder includes only the rooms it may use.
# The same table is in core/CMakeLists.txt (each room's USES); keep the two together.
declare -A uses=(
  [base]=""
  [volume]="base"
  [octree]="base volume"
  [camera]="base volume"
  [appearance]="base volume camera"
  [image]="base camera"
  [streaming]="base volume octree camera appearance"
  [reference]="base volume octree camera appearance image streaming"
)
for f in "$root"/core/*; do
  [ -f "$f" ] || continue
  case "$(basename "$f")" in CMakeLists.txt) ;; *) echo "RULE BROKEN: core/ holds a file outside its rooms: $f"; fail=1 ;; esac
done
for dir in "$root"/core/*/; do
  room=$(basename "$dir")
  if [ -z "${uses[$room]+set}" ]; then echo "RULE BROKEN: core/$room/ is not a room of the table"; fail=1; continue; fi
  while IFS= read -r hit; do
    [ -n "$hit" ] || continue
    used=$(sed -E 's#.*\#include *"core/([A-Za-z_]+)/.*#\1#' <<<"$hit")
    [ "$used" = "$room" ] && continue
    case " ${uses[$room]} " in *" $used "*) ;; *)
      echo "RULE BROKEN: core/$room may use only [${uses[$room]}], not core/$used: $hit"; fail=1 ;;
    esac
  done < <(grep -rnE '#include *"core/[A-Za-z_]+/' "$dir" --include='*.h' --include='*.cpp' --include='*.glsl')
done
# Each module exists as its folder.
for d in app ui core render dicom resources tests installer; do
  [ -d "$root/$d" ] || { echo "missing module folder $d/"; fail=1; }
done
[ $fail -eq 0 ] && echo "module dependency rule holds"
exit $fail
