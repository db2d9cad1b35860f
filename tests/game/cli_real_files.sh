#!/bin/bash
# Issue 39's reproductions with the bytes real files hold (a shell writes them; CMake's strings are
# text): each a clear refusal or correct handling, a normal exit, and nothing half written.
# Usage: cli_real_files.sh IKEBANA ASSETS WORKDIR
set -u
ikebana=$1 assets=$2 out=$3/real_files
rm -rf "$out" && mkdir -p "$out" && cd "$out" || exit 1
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }
# run WHAT EXPECTED_RC EXPECTED_TEXT COMMAND...: the exit code and a line of the output.
run() {
    local what=$1 rc=$2 text=$3
    shift 3
    local said got
    said=$(timeout 300 "$@" 2>&1)
    got=$?
    [ "$got" = "$rc" ] || fail "$what: exit $got, expected $rc: $said"
    grep -qF -- "$text" <<<"$said" || fail "$what: does not say '$text': $said"
}

# 1. Text that is not UTF-8.
run "a trainee's name in Latin-1" 2 "ikebana: --trainee: not UTF-8 text (byte 0xEB at position 3)" \
    "$ikebana" --lesson sogetsu_basic_upright --trainee $'Zo\xeb' --db "$out/b.db" --frames 1
[ -e "$out/b.db" ] && fail "the refused name made a database"
run "--env with a byte that is not UTF-8" 2 "--env 'vase="$'\xef\xbf\xbd'"': not UTF-8 text (byte 0xFF at position 6)" \
    "$ikebana" sim --seconds 0.1 --env $'vase=\xff'
python3 -c "open('small.csv','wb').write(b'flower_id,insertion,max_force_gf,lot\n'+b''.join(b'F%d,%d,%d,%s\n'%(f,k,450-30*k+(7 if f%2 else -7),b'\xff' if f%2 else b'ok') for f in range(8) for k in (1,2)))"
run "validate on a Windows-1252 cell" 0 "note: small.csv:4:10: byte 0xFF is not UTF-8: the file is read as Windows-1252 (Latin-1), as spreadsheets write it" \
    "$ikebana" validate small.csv --json val.json --write-species ext.json
python3 -c "import json; j=json.load(open('val.json')); print('ok')" >/dev/null 2>&1 || fail "val.json is not JSON"
grep -q "ÿ" val.json || fail "the cell 0xFF is not ÿ in val.json"

# 2. A quoted cell with a line break, as a spreadsheet writes a note with Enter in it.
printf 'flower_id,insertion,max_force_gf,note\r\nF1,1,484,"Zoe\r\nNakamura"\r\nF1,2,452,"x, ""y"""\r\nF2,1,470,ok\r\n' > multi.csv
run "predict on a quoted line break" 0 "wrote 3 predictions to pred.csv" "$ikebana" predict multi.csv -o pred.csv
[ "$(sed -n 3p pred.csv | tr -d '\r' | cut -d, -f1)" = "Nakamura\"" ] || fail "the prediction is not at the end of the row's last line: $(cat pred.csv)"
grep -q '^F1,1,484,"Zoe' pred.csv || fail "the row's first line changed: $(cat pred.csv)"

# 3. A row of millions of commas: refused at its width, in bounded memory (1 GB here; it took 2.7).
python3 -c "open('wide.csv','w').write('flower_id,insertion,max_force_gf\n'+','*30000000+'\n')"
# (A sanitizer's shadow memory does not fit under such a limit: there the row is refused without it.)
limit="ulimit -v 1000000;"
ldd "$ikebana" | grep -qE "lib(a|t)san" && limit=""
run "a 30 M-comma row under a 1 GB limit" 2 "wide.csv:2:1: expected 3 fields (as the header), found 30000001" \
    bash -c "$limit exec \"$ikebana\" predict wide.csv -o wide_out.csv"

# 4. --db on a FIFO or a device: refused at once.
mkfifo f.db
run "history --db FIFO" 1 "f.db: a FIFO, not a progress database" "$ikebana" history --db f.db
run "lesson demo --db FIFO" 2 "ikebana lesson demo: --db: f.db: a FIFO, not a progress database" "$ikebana" lesson demo sogetsu_basic_upright --db f.db
run "history --db /dev/zero" 1 "/dev/zero: a device or socket, not a progress database" "$ikebana" history --db /dev/zero
[ -e /dev/zero-journal ] && fail "/dev/zero-journal was made"

# 6. Values that lie.
run "--rate render=0x10" 2 "rate 'render': '0x10' is not a number of Hz" "$ikebana" sim --seconds 0.1 --rate render=0x10
sed 's/"direction": \[0.5, 0.0, 0.866\]/"direction": [1e200, 1e200, 1e200]/' "$assets/scenes/default.json" > huge.json
grep -q 1e200 huge.json || fail "the scene has no direction to change"
said=$("$ikebana" sim --scene huge.json --seconds 0.2 2>&1) || fail "a direction of [1e200, 1e200, 1e200]: $said"
grep -qi "nan" <<<"$said" && fail "a direction of [1e200, 1e200, 1e200] gave NaN: $said"

# 7. A command that fails writes nothing.
mkdir -p rep && ln -s "$out/victim.md" rep/report.md && echo keep > victim.md
run "validate with a planted link in the report" 1 "rep/report.md: is a symbolic link" \
    "$ikebana" validate small.csv --json val2.json --report rep --write-species ext2.json
for f in val2.json ext2.json rep/model_vs_data.svg; do [ -e "$f" ] && fail "$f was written by a failed validate"; done
[ "$(cat victim.md)" = keep ] || fail "the link's target was written"
ln -sf "$out/victim.md" victim.md.link
run "validate with --write-species a link" 2 "victim.md.link: is a symbolic link" \
    "$ikebana" validate small.csv --json val3.json --report new/deep/rep --write-species victim.md.link
[ -e new ] && fail "a failed validate left the report folder it made"
[ -e val3.json ] && fail "a failed validate wrote val3.json"

# (No Vulkan driver stands in for a device that refuses the size: 8192 x 8192 renders on this lavapipe.)
run "render without a device" 3 "ikebana render:" env VK_ICD_FILENAMES=/nonexistent.json VK_DRIVER_FILES=/nonexistent.json "$ikebana" render --out renders/big
[ -e renders ] && fail "a failed render left its --out folder"

# 8. Paths a data file may name: only inside its folder or the assets folder, one answer either way.
mkdir -p designer
sed 's|"mesh": "[^"]*"|"mesh": "/etc/shadow"|' "$assets/species/sunflower.json" > designer/shadow.json
sed 's|"mesh": "[^"]*"|"mesh": "/etc/no-such-file-here"|' "$assets/species/sunflower.json" > designer/nothing.json
run "a mesh at /etc/shadow" 1 "\"/etc/shadow\" is outside shadow.json's folder and the assets folder" "$ikebana" species check designer/shadow.json
run "a mesh at a path that does not exist" 1 "\"/etc/no-such-file-here\" is outside nothing.json's folder and the assets folder" \
    "$ikebana" species check designer/nothing.json

[ "$failures" = 0 ] && echo "all real-world files handled" && exit 0
exit 1
