# One owner per file kind (issue 43): the ACAP kind's datasets, the skeleton kind's and the
# components kind's are named only in libshared/io/ (io/acap_file, io/skeleton_file,
# io/components_file), and so are the model kinds' (io/model_file: the training state and log they
# share, and each model's own groups by name); every other module reads and writes them through
# those.
source "$(dirname "$0")/lib.sh"
: "${DF_SOURCE:?}"
# a dataset name given to a call: f.read<float>("/features/raw"), f.exists("/frames/source"), ...
acap='[(,] *"/(template|frames|features|sequences|classes|normalization|synthetic)[/"]'
found=$(grep -rnE "$acap" "$DF_SOURCE/libshared" --include='*.cpp' --include='*.h' | grep -v "^$DF_SOURCE/libshared/io/" |
  grep -vE '^[^:]*:[0-9]+: *//' || true)
[ -z "$found" ] || fail "ACAP datasets named outside libshared/io (use io/acap_file.h):
$found"
found=$(grep -rnE '[(,] *"/(poses|skeleton)[/"]' "$DF_SOURCE/libshared" --include='*.cpp' --include='*.h' |
  grep -v "^$DF_SOURCE/libshared/io/" || true)
[ -z "$found" ] || fail "skeleton datasets named outside libshared/io (use io/skeleton_file.h):
$found"
# The components kind: its levels (named by fmt::format("/level{}", l) too), masks, similarity.
found=$(grep -rnE '(\(|,) *"/(level[0-9{]|attention|similarity)' "$DF_SOURCE/libshared" --include='*.cpp' --include='*.h' |
  grep -v "^$DF_SOURCE/libshared/io/" | grep -vE '^[^:]*:[0-9]+: *//' || true)
[ -z "$found" ] || fail "components datasets named outside libshared/io (use io/components_file.h):
$found"
# Any dataset or group name given to a call outside io/ (the model kinds' included: /params,
# /optimizer, /rng, /training, /config, /split, ...) is a file kind without an owner.
any='[(,] *"/[a-z_]+[/"a-z0-9_{}.]*"'
found=$(grep -rnE "$any" "$DF_SOURCE/libshared" --include='*.cpp' --include='*.h' |
  grep -v "^$DF_SOURCE/libshared/io/" | grep -vE '^[^:]*:[0-9]+: *//' || true)
[ -z "$found" ] || fail "an HDF5 dataset named outside io/ (name it in io/model_file.h or the kind's owner):
$found"
# and the check can fail: a line naming one outside io is found
mkdir -p probe/models && echo 'auto x = f.read<float>("/features/raw");' >probe/models/x.cpp
grep -rqE "$acap" probe || fail "the pattern misses a dataset name"
echo 'f.set_attr("/config", "kz", kz);' >probe/models/z.cpp
grep -rqE "$any" probe || fail "the pattern misses a model kind's group"
echo 'const auto g = fmt::format("/level{}", l);' >probe/models/y.cpp
grep -rqE '(\(|,) *"/(level[0-9{]|attention|similarity)' probe || fail "the components pattern misses a dataset name"
echo "ok"
