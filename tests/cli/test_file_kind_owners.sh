# One owner per file kind (issue 43): the ACAP kind's datasets, the skeleton kind's and the
# components kind's are named only in libshared/io/ (io/acap_file, io/skeleton_file,
# io/components_file); every other module reads and writes them through those. The model kinds' (/params, /training, the ActGAN model's copy of the
# skeleton) belong to their models/ files and are not checked here.
source "$(dirname "$0")/lib.sh"
: "${DF_SOURCE:?}"
# a dataset name given to a call: f.read<float>("/features/raw"), f.exists("/frames/source"), ...
acap='[(,] *"/(template|frames|features|sequences|classes|normalization|synthetic)[/"]'
found=$(grep -rnE "$acap" "$DF_SOURCE/libshared" --include='*.cpp' --include='*.h' | grep -v "^$DF_SOURCE/libshared/io/" |
  grep -v "libshared/models/actgan/model.cpp" | grep -vE '^[^:]*:[0-9]+: *//' || true)
[ -z "$found" ] || fail "ACAP datasets named outside libshared/io (use io/acap_file.h):
$found"
# The ActGAN model file stores its class names and skeleton beside its networks: its own kind.
found=$(grep -rnE '[(,] *"/(poses|skeleton)[/"]' "$DF_SOURCE/libshared" --include='*.cpp' --include='*.h' |
  grep -v "^$DF_SOURCE/libshared/io/" | grep -v "libshared/models/actgan/model.cpp" || true)
[ -z "$found" ] || fail "skeleton datasets named outside libshared/io (use io/skeleton_file.h):
$found"
# The components kind: its levels (named by fmt::format("/level{}", l) too), masks, similarity.
found=$(grep -rnE '(\(|,) *"/(level[0-9{]|attention|similarity)' "$DF_SOURCE/libshared" --include='*.cpp' --include='*.h' |
  grep -v "^$DF_SOURCE/libshared/io/" | grep -vE '^[^:]*:[0-9]+: *//' || true)
[ -z "$found" ] || fail "components datasets named outside libshared/io (use io/components_file.h):
$found"
# The model kinds: each is named only by its owner (models/<method>/model.cpp), the parts they
# share (models/common/model_file.cpp: template, normalization, log; nn/checkpoint.cpp: weights,
# optimizer and RNG state). Any other dataset name outside io/ is a file kind without an owner.
found=$(grep -rnE '[(,] *"/[a-z_]+[/"a-z0-9_{}.]*"' "$DF_SOURCE/libshared" --include='*.cpp' --include='*.h' |
  grep -v "^$DF_SOURCE/libshared/io/" | grep -vE '^[^:]*:[0-9]+: *//' |
  grep -vE "libshared/models/(bdlstm|msae|actgan)/model.cpp:|libshared/models/common/model_file.cpp:|libshared/nn/checkpoint.cpp:" || true)
[ -z "$found" ] || fail "an HDF5 dataset named outside io/ and the model kinds' owners:
$found"
# and the check can fail: a line naming one outside io is found
mkdir -p probe/models && echo 'auto x = f.read<float>("/features/raw");' >probe/models/x.cpp
grep -rqE "$acap" probe || fail "the pattern misses a dataset name"
echo 'const auto g = fmt::format("/level{}", l);' >probe/models/y.cpp
grep -rqE '(\(|,) *"/(level[0-9{]|attention|similarity)' probe || fail "the components pattern misses a dataset name"
echo "ok"
