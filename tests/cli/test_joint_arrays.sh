# Joint arrays in (issue 71): skel2h5 reads .npy files (and .npz archives of them) of [frames, joints, 3] positions — a
# directory of class folders, a labels list with subjects, a joint layout given or recognised by
# the count, C and Fortran order, float32/float64 — and the imported set trains and generates end
# to end. The arrays are written here (perl: no numpy needed): rigid motions of a rest skeleton,
# so that every bone keeps its length.
source "$(dirname "$0")/lib.sh"
: "${DF_PLUGIN_DIR:?}"
export HDF5_PLUGIN_PATH=$DF_PLUGIN_DIR

# npy OUT FRAMES JOINTS AXIS PHASE [DTYPE] [ORDER]: a skeleton of JOINTS joints (joint j at
# (0.1 j, 0.05 j^2 mod 0.7, 0.02 j)), turned about AXIS (x or y) by 0.6 sin(0.3 t + PHASE) at frame t;
# DTYPE f4 (default) or f8; ORDER C (default) or F (Fortran).
npy() {
  perl -e '
    my ($out, $T, $J, $axis, $phase, $dt, $order) = @ARGV;
    $dt ||= "f4"; $order ||= "C";
    my @v;  # [t][j][c]
    for my $t (0 .. $T - 1) {
      my $a = 0.6 * sin(0.3 * $t + $phase); my ($c, $s) = (cos($a), sin($a));
      for my $j (0 .. $J - 1) {
        my ($x, $y, $z) = (0.1 * $j, (0.05 * $j * $j) - 0.7 * int(0.05 * $j * $j / 0.7), 0.02 * $j);
        ($y, $z) = ($c * $y - $s * $z, $s * $y + $c * $z) if $axis eq "x";
        ($x, $z) = ($c * $x + $s * $z, -$s * $x + $c * $z) if $axis eq "y";
        $v[$t][$j] = [$x, $y, $z];
      }
    }
    my @flat;
    if ($order eq "F") { for my $c (0 .. 2) { for my $j (0 .. $J - 1) { for my $t (0 .. $T - 1) { push @flat, $v[$t][$j][$c] } } } }
    else { for my $t (0 .. $T - 1) { for my $j (0 .. $J - 1) { push @flat, @{$v[$t][$j]} } } }
    my $h = sprintf("{\x27descr\x27: \x27<%s\x27, \x27fortran_order\x27: %s, \x27shape\x27: (%d, %d, 3), }",
                    $dt, $order eq "F" ? "True" : "False", $T, $J);
    $h .= " " x (63 - (10 + length($h)) % 64) . "\n";
    open(my $f, ">:raw", $out) or die;
    print $f "\x93NUMPY\x01\x00" . pack("v", length($h)) . $h . pack($dt eq "f8" ? "d<*" : "f<*", @flat);
  ' "$@"
}

# --- a directory of class folders, SMPL's 22 joints recognised by their count
mkdir -p set/turn set/nod
for k in 1 2 3 4; do
  npy set/turn/turn_$k.npy 24 22 y "0.$k"
  npy set/nod/nod_$k.npy 24 22 x "0.$k"
done
skel2h5 set --source-fps 20 --length 12 --clip-stride 6 --test-fraction 0.25 --seed 2 -o folders.h5 2>folders.log
h5check -q --kind skeleton folders.h5
grep -q "22 joints: taken as SMPL's 22 body joints" folders.log || fail "the layout was not named: $(cat folders.log)"
classes=$(h5dump -d /classes/names -y folders.h5 | grep -o '"[a-z]*"' | tr -d '"' | xargs)
[ "$classes" = "nod turn" ] || [ "$classes" = "turn nod" ] || fail "classes '$classes', expected the folders' names"
h5dump -d /skeleton/joint_names -y folders.h5 | grep -q '"left_wrist"' || fail "SMPL's joint names missing"
rate=$(h5dump -a /frame_rate folders.h5 | awk '/\(0\):/ { print $2 }')
[ "$rate" = 20 ] || fail "frame rate $rate, expected --source-fps 20"
# 8 sequences of 24 frames in clips of 12 every 6: 3 clips each
offsets=$(h5_data folders.h5 /sequences/offsets | tr -c '0-9' ' ' | wc -w)
[ "$offsets" = 25 ] || fail "$((offsets - 1)) clips, expected 24"
echo "ok (class folders, SMPL 22 recognised)"

# --- a labels list with subjects; float64 and Fortran order read as the same poses
mkdir -p flat
for k in 1 2 3 4; do
  npy flat/a$k.npy 24 22 y "0.$k" f8
  npy flat/b$k.npy 24 22 x "0.$k" f4 F
done
printf '# name class subject\na1 turn 1\na2 turn 2\na3 turn 1\na4 turn 2\nb1 nod 1\nb2 nod 2\nb3 nod 1\nb4 nod 2\n' >labels.txt
skel2h5 -q flat --labels labels.txt --source-fps 20 --length 12 --clip-stride 6 --test-subjects 2 -o listed.h5
h5check -q --kind skeleton listed.h5
read -r -a tests <<<"$(h5_data listed.h5 /sequences/test | tr -c '0-9' ' ')"
read -r -a subjects <<<"$(h5_data listed.h5 /sequences/subjects | tr -c '0-9' ' ')"
[ "${#tests[@]}" = 24 ] && [ "${#subjects[@]}" = 24 ] || fail "${#tests[@]} clips, expected 24"
for i in "${!tests[@]}"; do
  [ "${tests[$i]}" = $(( subjects[i] == 2 )) ] || fail "clip $i of subject ${subjects[$i]} has test ${tests[$i]}"
done
# the Fortran-order float32 arrays hold the same poses as C-order float32 ones
mkdir -p c f
npy c/x.npy 24 22 x 0.1; npy f/x.npy 24 22 x 0.1 f4 F
skel2h5 -q --label nod --source-fps 20 --raw c/x.npy -o c.h5
skel2h5 -q --label nod --source-fps 20 --raw f/x.npy -o f.h5
run h5diff c.h5 f.h5 /poses; expect_rc 0
echo "ok (labels list, subjects held out, float64, Fortran order)"

# --- a layout given: 7 joints named by --joints; without it the count is refused
mkdir -p seven/arm
for k in 1 2 3; do npy seven/arm/arm_$k.npy 20 7 y "0.$k"; done
printf 'root -\nspine root\nneck spine\nhead neck\nshoulder neck\nelbow shoulder\nhand elbow\n' >joints.txt
skel2h5 -q seven --joints joints.txt --length 10 -o seven.h5
h5dump -d /skeleton/joint_names -y seven.h5 | grep -q '"elbow"' || fail "--joints names missing"
run skel2h5 -q seven --length 10 -o x.h5
expect_rc 1; expect_one_error_line skel2h5; expect_err "7 joints per frame, not a layout skel2h5 knows.*--joints"
printf 'root -\nspine root\nneck spine\nhead nose\n' >bad-joints.txt
run skel2h5 -q seven --joints bad-joints.txt -o x.h5
expect_rc 1; expect_one_error_line skel2h5; expect_err "parent 'nose' is not an earlier joint \\(bad-joints.txt:4\\)"
echo "ok (a joint layout given, an unknown count refused)"

# --- bad input: one line each, naming the file
printf 'a1 turn 1\n' >short-labels.txt
run skel2h5 -q flat --labels short-labels.txt -o x.h5
expect_rc 1; expect_one_error_line skel2h5; expect_err "has no line 'a2 CLASS' in short-labels.txt"
head -c 100 set/turn/turn_1.npy >cut.npy  # inside the header
run skel2h5 -q --label x cut.npy -o x.h5
expect_rc 1; expect_one_error_line skel2h5; expect_err "a truncated .npy header \\(cut.npy\\)"
head -c 1000 set/turn/turn_1.npy >cut.npy  # inside the data
run skel2h5 -q --label x cut.npy -o x.h5
expect_rc 1; expect_one_error_line skel2h5; expect_err "a truncated .npy array.*elements of <f4 \\(cut.npy\\)"
perl -e 'my $h = "{\x27descr\x27: \x27>f4\x27, \x27fortran_order\x27: False, \x27shape\x27: (2, 22, 3), }"; $h .= " " x (63 - (10 + length($h)) % 64) . "\n"; print "\x93NUMPY\x01\x00" . pack("v", length($h)) . $h . ("\0" x 528)' >big.npy
run skel2h5 -q --label x big.npy -o x.h5
expect_rc 1; expect_one_error_line skel2h5; expect_err "dtype '>f4'"
npy flat2.npy 24 22 y 0.1
run skel2h5 -q flat2.npy -o x.h5   # in the working directory: no folder to name the class
expect_rc 1; expect_one_error_line skel2h5; expect_err "has no class"
printf 'not an array' >junk.npy
run skel2h5 -q --label x junk.npy -o x.h5
expect_rc 1; expect_one_error_line skel2h5; expect_err "not a .npy array"
echo "ok (bad input)"

# --- .npz archives (np.savez / np.savez_compressed): zipped .npy members, stored or deflated, with
# zip64 records as numpy writes them (perl's core IO::Compress::Zip here); classes and subjects
# from members of the archive
# npy_text OUT WORD...: a .npy of unicode strings ('<U n'), one WORD or a list of them
npy_text() {
  perl -e '
    my ($out, @w) = @ARGV; my $n = 1; for (@w) { $n = length if length > $n }
    my $shape = @w == 1 ? "()" : sprintf("(%d,)", scalar @w);
    my $h = sprintf("{\x27descr\x27: \x27<U%d\x27, \x27fortran_order\x27: False, \x27shape\x27: %s, }", $n, $shape);
    $h .= " " x (63 - (10 + length($h)) % 64) . "\n";
    open(my $f, ">:raw", $out) or die;
    print $f "\x93NUMPY\x01\x00" . pack("v", length($h)) . $h;
    print $f pack("V*", map(ord, split(//, $_)), (0) x ($n - length)) for @w;
  ' "$@"
}
# npy_int OUT N...: a .npy list of int64
npy_int() {
  perl -e '
    my ($out, @v) = @ARGV;
    my $h = sprintf("{\x27descr\x27: \x27<i8\x27, \x27fortran_order\x27: False, \x27shape\x27: (%d,), }", scalar @v);
    $h .= " " x (63 - (10 + length($h)) % 64) . "\n";
    open(my $f, ">:raw", $out) or die;
    print $f "\x93NUMPY\x01\x00" . pack("v", length($h)) . $h . pack("q<*", @v);
  ' "$@"
}
# npz OUT METHOD MEMBER.npy...: a zip of the members (METHOD store or deflate), zip64 records
npz() {
  perl -MIO::Compress::Zip=:all -e '
    my ($out, $method, @files) = @ARGV;
    zip(\@files => $out, FilterName => sub { s{.*/}{} }, Zip64 => 1,
        Method => $method eq "store" ? ZIP_CM_STORE : ZIP_CM_DEFLATE) or die $ZipError;
  ' "$@"
}
mkdir -p npz/one npz/many npz/arch
for k in 1 2 3 4; do  # one sequence per archive, its class a member 'label'
  npy npz/one/joints.npy 24 22 y "0.$k"; npy_text npz/one/label.npy turn
  npz npz/arch/turn_$k.npz deflate npz/one/joints.npy npz/one/label.npy
  npy npz/one/joints.npy 24 22 x "0.$k"; npy_text npz/one/label.npy nod
  npz npz/arch/nod_$k.npz store npz/one/joints.npy npz/one/label.npy
done
skel2h5 -q npz/arch --source-fps 20 --length 12 --clip-stride 6 --test-fraction 0.25 --seed 2 -o archives.h5
h5check -q --kind skeleton archives.h5
classes=$(h5dump -d /classes/names -y archives.h5 | grep -o '"[a-z]*"' | tr -d '"' | xargs)
[ "$classes" = "nod turn" ] || [ "$classes" = "turn nod" ] || fail "classes '$classes', expected the archives' labels"
# the same poses as the .npy files of the class folders above (turn_1 .. turn_4, nod_1 .. nod_4)
skel2h5 -q --raw --source-fps 20 npz/arch/turn_2.npz -o turn2-npz.h5
skel2h5 -q --raw --source-fps 20 set/turn/turn_2.npy -o turn2-npy.h5
run h5diff turn2-npz.h5 turn2-npy.h5 /poses; expect_rc 0
# several sequences in one archive: labels as integers, subjects, a member that is not an array of joints
for k in 1 2 3 4; do npy npz/many/s$k.npy 24 22 $([ $k -le 2 ] && echo x || echo y) "0.$k"; done
npy_int npz/many/labels.npy 7 7 9 9
npy_int npz/many/subjects.npy 1 2 1 2
npy_int npz/many/fps.npy 20
npz npz/set.npz deflate npz/many/s1.npy npz/many/s2.npy npz/many/s3.npy npz/many/s4.npy npz/many/labels.npy npz/many/subjects.npy npz/many/fps.npy
run skel2h5 npz/set.npz --source-fps 20 --test-subjects 2 -o set.h5; expect_rc 0
expect_err "members that are not joint arrays were left out: fps \(1\)"
[ "$(h5dump -d /sequences/names -y set.h5 | grep -o '"set/s[0-9]"' | tr -d '"' | xargs)" = "set/s1 set/s2 set/s3 set/s4" ] ||
  fail "names: $(h5dump -d /sequences/names -y set.h5)"
[ "$(h5dump -d /classes/names -y set.h5 | grep -o '"[0-9]*"' | tr -d '"' | xargs)" = "7 9" ] || fail "integer labels: $(h5dump -d /classes/names -y set.h5)"
[ "$(h5_data set.h5 /sequences/test | tr -c '0-9' ' ' | xargs)" = "0 1 0 1" ] || fail "subjects 2 not held out: $(h5_data set.h5 /sequences/test)"
# a labels list names a member as STEM/MEMBER, and wins over the archive
printf 'set/s1 a\nset/s2 a\nset/s3 b\nset/s4 b\n' >npz-labels.txt
skel2h5 -q npz/set.npz --labels npz-labels.txt -o relabelled.h5
[ "$(h5dump -d /classes/names -y relabelled.h5 | grep -o '"[a-z]"' | tr -d '"' | xargs)" = "a b" ] || fail "the labels list did not win"
# bad archives: one line each, naming the archive (and member)
npy_int npz/many/labels.npy 7 7 9
npz npz/short.npz store npz/many/s1.npy npz/many/s2.npy npz/many/labels.npy
run skel2h5 -q npz/short.npz -o x.h5
expect_rc 1; expect_one_error_line skel2h5; expect_err "3 values for the archive's 2 sequences \(npz/short.npz \(labels\)\)"
npz npz/nojoints.npz store npz/many/fps.npy
run skel2h5 -q npz/nojoints.npz -o x.h5
expect_rc 1; expect_one_error_line skel2h5; expect_err "no member of shape \[frames, joints, 3\] \(members: fps \(1\)\)"
head -c 3000 npz/set.npz >npz/cut.npz
run skel2h5 -q --label x npz/cut.npz -o x.h5
expect_rc 1; expect_one_error_line skel2h5; expect_err "not a .npz archive \(no zip directory\) \(npz/cut.npz\)"
cp npz/arch/nod_1.npz npz/flipped.npz  # a stored member: flip a byte of its data, the CRC tells
printf '\x42' | dd of=npz/flipped.npz bs=1 seek=2000 conv=notrunc status=none
run skel2h5 -q --label x npz/flipped.npz -o x.h5
expect_rc 1; expect_one_error_line skel2h5; expect_err "CRC mismatch"
[ -f x.h5 ] && fail "output written after an error"
echo "ok (.npz archives: stored and deflated, labels and subjects inside, names STEM/MEMBER, bad archives)"

# --- and it trains and generates end to end
train-actgan -q --noise 4 --latent 3 --hidden 16 --fc 32 --batch 8 --pretrain-batch 16 --print-every 10 --seed 3 \
  --pretrain-iterations 10 --iterations 10 folders.h5 -o model.h5
h5check -q --kind actgan-model model.h5
gen-actgan -q model.h5 --class turn --count 2 -o gen.h5
h5check -q --kind skeleton gen.h5
echo "ok (train-actgan and gen-actgan on the imported arrays)"
