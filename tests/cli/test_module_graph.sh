# The modules of libshared include only what is above them (libshared/CMakeLists.txt's graph,
# issue 69): the mesh types and the feature normalization are core's, so geometry and nn include
# no file format (io) and link only core; every other module's includes stay inside its row.
source "$(dirname "$0")/lib.sh"
: "${DF_SOURCE:?}"
declare -A allowed=(
  [core]="core"
  [io]="core io"
  [geometry]="core geometry"
  [nn]="core nn"
  [synth]="core io synth"
  [convert]="core io geometry convert"
  [models]="core io geometry nn models"
  [eval]="core io geometry convert eval"
  [render]="core io render"
  [apps]="core io geometry nn synth convert models eval render apps"
)
# check DIR: every '#include "module/..."' under DIR/<module>/ names an allowed module
check() {
  local bad="" m inc
  for m in "${!allowed[@]}"; do
    [ -d "$1/$m" ] || continue
    while IFS= read -r inc; do
      local to=${inc#*#include \"}; to=${to%%/*}
      [[ " ${allowed[$m]} " == *" $to "* ]] || bad+="$m -> $to: $inc"$'\n'
    done < <(grep -rHnE '^#include "[a-z_]+/' "$1/$m" --include='*.h' --include='*.cpp' || true)
  done
  printf '%s' "$bad"
}
found=$(check "$DF_SOURCE/libshared")
[ -z "$found" ] || fail "includes against the module graph:
$found"
# Every module is in the table (a new one must be placed in the graph).
for d in "$DF_SOURCE"/libshared/*/; do
  m=$(basename "$d"); [ -n "${allowed[$m]:-}" ] || fail "module $m is not in the graph"
done
# geometry and nn link only core (CMake): their targets name no other df_ library.
for t in df_geometry df_nn; do
  links=$(grep -E "^target_link_libraries\($t PUBLIC" "$DF_SOURCE/libshared/CMakeLists.txt")
  [ "$(grep -oE 'df_[a-z]+' <<<"${links#*PUBLIC}" | xargs)" = df_core ] || fail "$t links: $links"
done
# and the check can fail: geometry including io, nn including models
mkdir -p probe/geometry probe/nn
echo '#include "io/mesh_io.h"' >probe/geometry/a.h
echo '#include "models/common/checkpoint.h"' >probe/nn/b.cpp
found=$(check probe)
grep -q "geometry -> io" <<<"$found" && grep -q "nn -> models" <<<"$found" ||
  fail "the check misses an include against the graph: '$found'"
echo "ok"
