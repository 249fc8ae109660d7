#!/usr/bin/env bash
# test_drive_sil_cli.sh DRIVE_SIL - the runner's command line: every bad
# input exits 2 and leaves no CSV; a good run exits 0 and writes one.
set -uo pipefail
bin=$1
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
fail=0
npass=0 nfail=0
pass() { echo "ok   $1"; npass=$((npass + 1)); }
failed() { echo "FAIL $1"; nfail=$((nfail + 1)); fail=1; }
good="$dir/good.ini"
printf '[controller]\nmode = open_loop\n[reference]\nuq_V = 20\n[run]\nduration_s = 0.01\n' > "$good"

# expect_bad NAME ARGS...: exit 2, a message on stderr, no CSV at $dir/out.csv
expect_bad() {
    local name=$1; shift
    rm -f "$dir"/out.csv*
    "$bin" "$@" > /dev/null 2> "$dir/err"
    local rc=$?
    if [ $rc -ne 2 ]; then
        failed "drive_sil CLI $name: exit $rc, expected 2"
    elif compgen -G "$dir/out.csv*" > /dev/null; then
        failed "drive_sil CLI $name: a CSV was left behind"
    elif ! [ -s "$dir/err" ]; then
        failed "drive_sil CLI $name: no message"
    else
        pass "drive_sil CLI $name: $(head -n 1 "$dir/err")"
    fi
}

bad() { printf '%b' "$2" > "$dir/$1.ini"; echo "$dir/$1.ini"; }

expect_bad "unknown flag" --scenario "$good" --out "$dir/out.csv" --fast
expect_bad "missing --out" --scenario "$good"
expect_bad "missing file" --scenario "$dir/none.ini" --out "$dir/out.csv"
expect_bad "unknown section" --scenario "$(bad s '[motor]\nR_ohm = 3\n')" --out "$dir/out.csv"
expect_bad "unknown key" --scenario "$(bad k '[plant]\nRs = 3\n')" --out "$dir/out.csv"
expect_bad "malformed number" --scenario "$(bad n '[plant]\nL_H = 11mH\n')" --out "$dir/out.csv"
expect_bad "malformed profile" --scenario "$(bad p '[reference]\nspeed_rpm = 0:0, 0.1 500\n')" --out "$dir/out.csv"
expect_bad "unknown method" --scenario "$(bad m '[controller]\nmethod = better\n')" --out "$dir/out.csv"
expect_bad "proposed without step 1" --scenario "$(bad q '[controller]\nmethod = proposed\n')" --out "$dir/out.csv"
if ! grep -q "q.ini:2: \[identify\] mode: " "$dir/err"; then
    failed "drive_sil CLI proposed without step 1: message is not FILE:LINE: [identify] mode: ..."
fi
expect_bad "unknown mode" --scenario "$(bad o '[controller]\nmode = position\n')" --out "$dir/out.csv"
expect_bad "unknown model" --scenario "$(bad i '[plant]\nmodel = pwm\n')" --out "$dir/out.csv"
expect_bad "zero duration" --scenario "$(bad z '[run]\nduration_s = 0\n')" --out "$dir/out.csv"
expect_bad "negative duration" --scenario "$good" --set run.duration_s=-1 --out "$dir/out.csv"
expect_bad "bad --set" --scenario "$good" --set plant.nokey=1 --out "$dir/out.csv"
expect_bad "unwritable output" --scenario "$good" --out "$dir/no/such/dir/out.csv"
# the link's flags (tools/sil/link_sil.h)
expect_bad "--baud without --link" --scenario "$good" --out "$dir/out.csv" --baud 9600
expect_bad "--link of no kind" --scenario "$good" --out "$dir/out.csv" --link udp:5555
expect_bad "--link port out of range" --scenario "$good" --out "$dir/out.csv" --link tcp:70000
expect_bad "--baud out of range" --scenario "$good" --out "$dir/out.csv" --link tcp:0 --baud 12
expect_bad "negative --realtime" --scenario "$good" --out "$dir/out.csv" --link tcp:0 --realtime -1
expect_bad "--link with --batch" --scenario "$good" --link tcp:0 --batch

if "$bin" --help > /dev/null && "$bin" --scenario "$good" --out "$dir/out.csv" > /dev/null &&
        head -n 1 "$dir/out.csv" | grep -q '^t_s,' && ! compgen -G "$dir/out.csv.tmp*" > /dev/null; then
    pass "drive_sil CLI good run: exit 0, CSV written"
else
    failed "drive_sil CLI good run"
fi
# beside the CSV: the run's resolved values, --set included (the report reads them, not the INI)
rm -f "$dir/res.resolved.json"
if "$bin" --scenario "$good" --set plant.L_H=0.0165 --set controller.L_factor=0.5 --out "$dir/res.csv" > /dev/null &&
        python3 -c 'import json, sys; d = json.load(open(sys.argv[1]));
sys.exit(0 if d["plant"]["L_H"] == 0.0165 and abs(d["controller"]["L_H"] - 0.00825) < 1e-9 and
         d["overrides"] == ["plant.L_H=0.0165", "controller.L_factor=0.5"] and d["commission"] is False else 1)' \
            "$dir/res.resolved.json"; then
    pass "drive_sil CLI good run: res.resolved.json with the --set overrides, plant and controller values"
else
    failed "drive_sil CLI resolved values beside the CSV"
fi
# a commissioning's trace says so beside it (its plot's title)
if "$bin" --scenario "$(dirname "$0")/../../tools/scenarios/conv_motor_paper.ini" --commission "$dir/comm.ini" \
        --out "$dir/comm.csv" > /dev/null &&
        python3 -c 'import json, sys; d = json.load(open(sys.argv[1])); sys.exit(0 if d["commission"] is True else 1)' \
            "$dir/comm.resolved.json"; then
    pass "drive_sil CLI --commission --out: comm.resolved.json names the commissioning"
else
    failed "drive_sil CLI --commission --out: no commission in the resolved values"
fi
# a refused step 1 with on_refusal = conventional: exit 0, the warning in the summary line
refused=$(printf '[plant]\nmodel = averaged\n[controller]\nmethod = proposed\nR_factor = 2\nR_min_ohm = 4\n[identify]\nmode = windows\non_refusal = conventional\n[reference]\nspeed_rpm = 0:0, 0.2:500~\n[load]\ntorque_Nm = 0:2, 0.35:4\n[run]\nduration_s = 0.6\n' > "$dir/refused.ini"; echo "$dir/refused.ini")
if line=$("$bin" --scenario "$refused" --out "$dir/out.csv") && echo "$line" | grep -q "state 5 (RUN), fault 0 (NONE).*warning STEP1_REFUSED (RSID_OUT_OF_BAND)"; then
    pass "drive_sil CLI step 1 refused, conventional: $line"
else
    failed "drive_sil CLI step 1 refused, conventional: ${line:-no summary line}"
fi

# a write error (a full disk; here a file-size limit) exits 1 naming the file, and leaves no CSV
rm -f "$dir"/out.csv*
(trap '' XFSZ; ulimit -f 4; "$bin" --scenario "$good" --set run.log_every=1 --out "$dir/out.csv" > /dev/null 2> "$dir/err")
rc=$?
if [ $rc -eq 1 ] && grep -q -- "--out $dir/out.csv: write error" "$dir/err" && ! compgen -G "$dir/out.csv*" > /dev/null; then
    pass "drive_sil CLI write error: $(head -n 1 "$dir/err")"
else
    failed "drive_sil CLI write error: exit $rc, $(head -n 1 "$dir/err"), files: $(ls "$dir")"
fi
# a device is written in place, never renamed over: /dev/full fails, /dev/null takes the run
if [ -c /dev/full ]; then
    "$bin" --scenario "$good" --out /dev/full > /dev/null 2> "$dir/err"
    rc=$?
    if [ $rc -eq 1 ] && grep -q -- "--out /dev/full: write error" "$dir/err" && [ -c /dev/full ] &&
            ! compgen -G "/dev/full.*" > /dev/null; then
        pass "drive_sil CLI --out /dev/full: $(head -n 1 "$dir/err")"
    else
        failed "drive_sil CLI --out /dev/full: exit $rc, $(head -n 1 "$dir/err")"
    fi
fi
if "$bin" --scenario "$good" --out /dev/null > /dev/null && [ -c /dev/null ] && ! compgen -G "/dev/null.*" > /dev/null; then
    pass "drive_sil CLI --out /dev/null: exit 0, /dev/null still a device"
else
    failed "drive_sil CLI --out /dev/null"
fi

# summary mode (i11): bad input exits 2 and leaves no file; a good run's JSON names the fault
expect_bad "unwritable summary" --scenario "$good" --summary "$dir/no/such/dir/s.json"
expect_bad "bad --window" --scenario "$good" --summary "$dir/out.csv.json" --window 0.9:0.1
expect_bad "--batch with --out" --scenario "$good" --batch --out "$dir/out.csv"
if "$bin" --scenario "$good" --summary - | python3 -c 'import json, sys; d = json.load(sys.stdin);
sys.exit(0 if d["fault_name"] == "NONE" and d["window_rows"] > 0 else 1)' &&
        printf 'p1\tplant.nokey=1\np2\trun.duration_s=0.02\n' | "$bin" --scenario "$good" --batch |
        python3 -c 'import json, sys; a, b = (json.loads(l) for l in sys.stdin);
sys.exit(0 if "nokey" in a["error"] and b["id"] == "p2" and b["periods"] == 200 else 1)'; then
    pass "drive_sil CLI summary to stdout, and --batch: a refused point named, the next one run"
else
    failed "drive_sil CLI summary/batch"
fi

# exit status 3: a run that ends in FAULT, with every output written in full
fault_ini=$(printf '[controller]\nmode = open_loop\n[reference]\nuq_V = 20\n[faults]\ngate_trip_s = 0.005\n[run]\nduration_s = 0.01\nlog_every = 1\n' > "$dir/fault.ini"; echo "$dir/fault.ini")
rm -f "$dir"/flt.*
"$bin" --scenario "$fault_ini" --out "$dir/flt.csv" --summary "$dir/flt.json" > "$dir/out" 2> "$dir/err"
rc=$?
if [ $rc -eq 3 ] && [ "$(($(wc -l < "$dir/flt.csv") - 1))" -eq 100 ] && [ -z "$(tail -c 1 "$dir/flt.csv")" ] &&
        python3 -c 'import json, sys; s = json.load(open(sys.argv[1])); r = json.load(open(sys.argv[2]));
sys.exit(0 if s["fault_name"] == "HW_TRIP" and s["periods"] == 100 and r["plant"]["vdc_V"] > 0 else 1)' \
            "$dir/flt.json" "$dir/flt.resolved.json" &&
        grep -q "final state 6 (FAULT), fault 1 (HW_TRIP)" "$dir/out" && ! compgen -G "$dir/flt.*.tmp*" > /dev/null; then
    pass "drive_sil CLI a run ending in FAULT: exit 3, CSV (100 rows), .resolved.json and summary complete"
else
    failed "drive_sil CLI a run ending in FAULT: exit $rc, $(head -n 1 "$dir/err"), files: $(ls "$dir")"
fi
"$bin" --scenario "$fault_ini" --check > /dev/null 2>&1
rc_check=$?
printf 'p1\t\n' | "$bin" --scenario "$fault_ini" --batch > "$dir/out" 2> /dev/null
rc_batch=$?
if [ $rc_check -eq 0 ] && [ $rc_batch -eq 0 ] && grep -q '"fault_name": "HW_TRIP"' "$dir/out"; then
    pass "drive_sil CLI a faulting scenario: --check and --batch exit 0 (a faulted point is a result)"
else
    failed "drive_sil CLI a faulting scenario: --check exit $rc_check, --batch exit $rc_batch"
fi
# the help into a file first: grep -q stops reading at its match, and
# under pipefail the writer's SIGPIPE would fail the pipeline
"$bin" --help > "$dir/help" 2>&1
if grep -q "^  3    the run ended in FAULT" "$dir/help"; then
    pass "drive_sil CLI --help documents the exit status"
else
    failed "drive_sil CLI --help: no exit status 3"
fi

# --version: the source revision drive_sil was built from (git describe, "unknown" outside git)
rev=$(git -C "$(dirname "$0")" describe --always --dirty 2>/dev/null || echo unknown)
if [ "$("$bin" --version)" = "drive_sil $rev" ]; then
    pass "drive_sil CLI --version: drive_sil $rev"
else
    failed "drive_sil CLI --version: \"$("$bin" --version)\", expected \"drive_sil $rev\""
fi

# plausibility bounds: the absurd is refused naming key, value and bound; beyond-limit runs
# expect_bound NAME GREP ARGS...: bad input whose message matches GREP
expect_bound() {
    local name=$1 pattern=$2; shift 2
    expect_bad "$name" "$@"
    if ! grep -q -- "$pattern" "$dir/err"; then
        failed "drive_sil CLI $name: message \"$(head -n 1 "$dir/err")\" does not match \"$pattern\""
    fi
}
expect_bound "R absurd" "\[plant\] R_ohm: 5000 ohm.*0.001 .. 1000 ohm" --scenario "$good" --set plant.R_ohm=5000 --out "$dir/out.csv"
expect_bound "R profile absurd" "\[plant\] R_ohm: 1e-05 ohm (at t = 1 s).*0.001 .. 1000" --scenario "$good" --set "plant.R_ohm=0:3, 1:1e-5" --out "$dir/out.csv"
expect_bound "L absurd" "\[plant\] L_H: 1e+06 H.*1e-06 .. 10 H" --scenario "$(bad lb '[plant]\nL_H = 1e6\n')" --out "$dir/out.csv"
if ! grep -q "lb.ini:2: " "$dir/err"; then failed "drive_sil CLI L absurd: not FILE:LINE"; fi
expect_bound "psi_f absurd" "\[plant\] psif_Wb: 1e-05 Wb.*0.0001 .. 10 Wb" --scenario "$good" --set plant.psif_Wb=1e-5 --out "$dir/out.csv"
expect_bound "pole pairs absurd" "\[plant\] pole_pairs: 65 .*1 .. 64" --scenario "$good" --set plant.pole_pairs=65 --out "$dir/out.csv"
expect_bound "J absurd" "\[plant\] J_kgm2: 1e+09 kg m^2.*1e-08 .. 100 kg m^2" --scenario "$good" --set plant.J_kgm2=1e9 --out "$dir/out.csv"
expect_bound "bus absurd" "\[plant\] vdc_V: 1 V.*5 .. 1500 V" --scenario "$good" --set plant.vdc_V=1 --out "$dir/out.csv"
expect_bound "speed reference absurd" "\[reference\] speed_rpm: -200000 r/min.*-100000 .. 100000" --scenario "$good" --set "reference.speed_rpm=0:0, 0.005:-2e5" --out "$dir/out.csv"
expect_bound "controller L by factor absurd" "\[controller\] L_H: 110 H (L_factor 10000 x \[plant\] L_H).*1e-06 .. 10 H" --scenario "$good" --set controller.L_factor=1e4 --out "$dir/out.csv"
expect_bound "controller R absurd" "\[controller\] R_ohm: 1e-05 ohm.*0.001 .. 1000" --scenario "$good" --set controller.R_ohm=1e-5 --out "$dir/out.csv"
expect_bound "controller psi_f by factor absurd" "\[controller\] psif_Wb: 0.000024 Wb\|\[controller\] psif_Wb: 2.4e-05 Wb" --scenario "$good" --set controller.psif_factor=1e-4 --out "$dir/out.csv"
printf 'p1\tplant.J_kgm2=1e9\n' | "$bin" --scenario "$good" --batch > "$dir/out" 2> /dev/null
if grep -q '"error": "--set plant.J_kgm2=1e9: \[plant\] J_kgm2: 1e+09 kg m^2 is not plausible' "$dir/out"; then
    pass "drive_sil CLI --batch: an absurd point is refused by name"
else
    failed "drive_sil CLI --batch absurd point: $(head -c 200 "$dir/out")"
fi
# beyond the overspeed trip (2400 r/min) but plausible: runs, and may fault
"$bin" --scenario "$good" --set controller.mode=speed --set "reference.speed_rpm=5000" --out "$dir/out.csv" > /dev/null 2> "$dir/err"
rc=$?
if [ $rc -eq 0 ] || [ $rc -eq 3 ]; then
    pass "drive_sil CLI a speed reference above the overspeed trip runs (exit $rc)"
else
    failed "drive_sil CLI a speed reference above the overspeed trip: exit $rc, $(head -n 1 "$dir/err")"
fi
if "$bin" --help > "$dir/help" 2>&1 && grep -q "\[plant\] J_kgm2 *1e-08 .. 100 kg m^2" "$dir/help"; then
    pass "drive_sil CLI --help lists the plausibility bounds"
else
    failed "drive_sil CLI --help: no plausibility bounds"
fi

# messages that name the real problem, at FILE:LINE
expect_msg() {
    local name=$1 pattern=$2; shift 2
    expect_bad "$name" "$@"
    if ! grep -q -- "$pattern" "$dir/err"; then
        failed "drive_sil CLI $name: message \"$(head -n 1 "$dir/err")\" does not match \"$pattern\""
    fi
}
expect_msg "empty value" "ev.ini:2: \[plant\] R_ohm: no value" --scenario "$(bad ev '[plant]\nR_ohm =\n')" --out "$dir/out.csv"
expect_msg "empty profile value" "ep.ini:3: \[reference\] speed_rpm: no value" --scenario "$(bad ep '[reference]\n\nspeed_rpm =\n')" --out "$dir/out.csv"
expect_msg "duplicate key" "dk.ini:3: \[plant\] L_H: given twice (first at .*dk.ini:2)" --scenario "$(bad dk '[plant]\nL_H = 0.01\nL_H = 0.02\n')" --out "$dir/out.csv"
expect_msg "duplicate profile key" "dp.ini:3: \[plant\] R_ohm: given twice (first at .*dp.ini:2" --scenario "$(bad dp '[plant]\nR_ohm = 3\nR_ohm = 4\n')" --out "$dir/out.csv"
expect_msg "broken section line" "bh.ini:1: section line \"\[plant\" has no closing ']'" --scenario "$(bad bh '[plant\nL_H = 0.01\n')" --out "$dir/out.csv"
expect_msg "key before any section" "ks.ini:1: L_H: a key before any \[section\] line" --scenario "$(bad ks 'L_H = 0.01\n')" --out "$dir/out.csv"

# SIGINT, SIGTERM: the CSV kept under its name to the last whole row, .resolved.json
# written, no temporary left, exit 128 + signal
endless=$(printf '[controller]\nmode = open_loop\n[reference]\nuq_V = 20\n[run]\nduration_s = 1e5\nlog_every = 1\n' > "$dir/endless.ini"; echo "$dir/endless.ini")
for sig in INT TERM HUP; do
    rm -f "$dir"/sig.*
    set -m   # a job of its own: a background job would ignore SIGINT
    "$bin" --scenario "$endless" --out "$dir/sig.csv" --summary "$dir/sig.json" > /dev/null 2> "$dir/err" &
    pid=$!
    set +m
    for _ in $(seq 100); do   # until it writes (the handlers are in place by then)
        [ -n "$(find "$dir" -name 'sig.csv.tmp.*' -size +1k 2>/dev/null)" ] && break
        sleep 0.1
    done
    kill -s $sig $pid
    wait $pid
    rc=$?
    want=$((128 + $(kill -l $sig)))
    rows=$(($(wc -l < "$dir/sig.csv" 2>/dev/null || echo 1) - 1))
    if [ $rc -eq $want ] && [ -f "$dir/sig.resolved.json" ] && ! compgen -G "$dir/sig.*.tmp*" > /dev/null &&
            ! [ -e "$dir/sig.json" ] && [ -z "$(tail -c 1 "$dir/sig.csv")" ] &&
            grep -q "after $rows periods, $rows rows, kept in $dir/sig.csv" "$dir/err" &&
            awk -F, 'NR == 1 { n = NF } NR == 2 { t0 = $1 } NR == 3 { dt = $1 - t0 }
                     NF != n { bad = 1 } END { r = NR - 1; k = ($1 - t0) / dt + 1;
                     exit (bad || r < 3 || k < r - 0.5 || k > r + 0.5) }' "$dir/sig.csv"; then
        pass "drive_sil CLI SIG$sig: exit $rc, CSV of $rows whole rows (one a period), .resolved.json, no temporary"
    else
        failed "drive_sil CLI SIG$sig: exit $rc (want $want), $rows rows, $(tail -n 1 "$dir/err"), files: $(ls "$dir" | grep sig)"
    fi
done

# --max-csv-mb: the CSV ends at its last whole row under the limit, the run goes on
rm -f "$dir"/cap.*
"$bin" --scenario "$good" --set run.duration_s=0.5 --set run.log_every=1 --max-csv-mb 0.05 \
    --out "$dir/cap.csv" --summary "$dir/cap.json" > /dev/null 2> "$dir/err"
rc=$?
if [ $rc -eq 0 ] && [ "$(stat -c %s "$dir/cap.csv")" -le 52428 ] && [ "$(stat -c %s "$dir/cap.csv")" -gt 40000 ] &&
        [ -z "$(tail -c 1 "$dir/cap.csv")" ] && grep -q "warning: --out $dir/cap.csv: the CSV reached --max-csv-mb 0.05" "$dir/err" &&
        awk -F, 'NR == 1 { n = NF } NF != n { exit 1 }' "$dir/cap.csv" &&
        python3 -c 'import json, sys; sys.exit(0 if json.load(open(sys.argv[1]))["periods"] == 5000 else 1)' "$dir/cap.json"; then
    pass "drive_sil CLI --max-csv-mb 0.05: $(stat -c %s "$dir/cap.csv") bytes of whole rows, warning, the run went on (5000 periods)"
else
    failed "drive_sil CLI --max-csv-mb: exit $rc, $(stat -c %s "$dir/cap.csv" 2>/dev/null) bytes, $(head -n 1 "$dir/err")"
fi
expect_bad "bad --max-csv-mb" --scenario "$good" --out "$dir/out.csv" --max-csv-mb 0

# every CSV column documented in tools/sil/CSV_COLUMNS.md's table, in the header's order
doc="$(dirname "$0")/../../tools/sil/CSV_COLUMNS.md"
documented=$(awk -F'|' '/^\| --- /{ t = 1; next } t && /^\|/ { c = $2; gsub(/[ `]/, "", c); print c; next } t { t = 0 }' "$doc" | paste -sd, -)
header=$(head -n 1 "$dir/flt.csv")
if [ -n "$header" ] && [ "$documented" = "$header" ]; then
    pass "drive_sil CLI CSV columns: all $(echo "$header" | tr ',' '\n' | wc -l) documented in $doc, none extra"
else
    failed "drive_sil CLI CSV columns: header and $doc differ: $(diff <(echo "$header" | tr ',' '\n') <(echo "$documented" | tr ',' '\n') | tr '\n' ' ')"
fi

# the documented key list is the key table's (drive_sil --list-keys --markdown; `make scenario-keys` rewrites it)
keys_doc="$(dirname "$0")/../../tools/sil/SCENARIO_KEYS.md"
if "$bin" --list-keys --markdown > "$dir/keys.md" && cmp -s "$dir/keys.md" "$keys_doc"; then
    pass "drive_sil CLI key list: $keys_doc is drive_sil --list-keys --markdown"
else
    failed "drive_sil CLI key list: $keys_doc differs from drive_sil --list-keys --markdown (make scenario-keys): $(diff "$keys_doc" "$dir/keys.md" | head -n 4 | tr '\n' ' ')"
fi
expect_bad "--list-keys with another argument" --list-keys --text
# one table: every key of the list is in --help under its section, in the resolved JSON's
# "keys" as set or defaulted, and, when derived, in "derived" with the keys it comes from
"$bin" --help > "$dir/help.txt"
"$bin" --scenario "$good" --set controller.te_max_Nm=11 --out "$dir/keys.csv" > /dev/null
if python3 - "$dir/keys.md" "$dir/help.txt" "$dir/keys.resolved.json" > "$dir/keys.err" <<'PY'
import json, re, sys
rows = [l.split('|') for l in open(sys.argv[1]) if l.startswith('| ') and not l.startswith(('| section', '| ---'))]
keys = [(r[1].strip(), r[2].strip(), r[3].strip()) for r in rows]
help_keys, sec = set(), None
for line in open(sys.argv[2]):
    m = re.match(r'^  \[(\w+)\]$', line.rstrip())
    if m:
        sec = m.group(1)
    elif sec and re.match(r'^    \S', line):
        help_keys.add((sec, line.split()[0]))
    elif not line.startswith('    '):
        sec = None
res = json.load(open(sys.argv[3]))
bad = []
for s, k, d in keys:
    name = s + '.' + k
    if (s, k) not in help_keys:
        bad.append(name + ' not in --help')
    if name not in res['keys']:
        bad.append(name + ' not in the resolved keys')
    if d.startswith('derived') and res['derived'].get(name, {}).get('from') != d[len('derived: '):]:
        bad.append(name + ': derived in the list, not with those keys in the resolved "derived"')
want = {'controller.te_max_Nm': 'set', 'controller.i_limit_A': 'derived', 'plant.L_H': 'default', 'run.duration_s': 'set'}
for name, src in want.items():
    if res['keys'][name]['source'] != src:
        bad.append(name + ' source ' + res['keys'][name]['source'] + ', expected ' + src)
if res['derived']['controller.te_max_Nm']['source'] != 'set' or res['keys']['controller.te_max_Nm']['value'] != 11:
    bad.append('controller.te_max_Nm = 11 not resolved as set')
print(len(keys), '; '.join(bad))
sys.exit(1 if bad or len(keys) != len(res['keys']) or len(keys) < 50 else 0)
PY
then
    pass "drive_sil CLI one key table: $(cut -d' ' -f1 "$dir/keys.err") keys, each in --help, the resolved keys and (derived) the resolved derived values"
else
    failed "drive_sil CLI one key table: $(cat "$dir/keys.err")"
fi

# build levels 1-2 on the charged 311 V bus: exit 3, BUS_CHARGED named in the summary; on 12 V level 1 runs
for lvl in 1 2; do
    "$bin" --scenario "$good" --set run.level=$lvl --set run.duration_s=0.02 --summary "$dir/bus.json" > /dev/null 2>&1
    rc=$?
    if [ $rc -eq 3 ] && grep -q '"fault_name": "BUS_CHARGED"' "$dir/bus.json"; then
        pass "drive_sil CLI level $lvl on 311 V: exit 3, BUS_CHARGED in --summary"
    else
        failed "drive_sil CLI level $lvl on 311 V: exit $rc, $(grep -o '"fault_name": "[A-Z_]*"' "$dir/bus.json")"
    fi
done
"$bin" --scenario "$good" --set run.level=1 --set plant.vdc_V=12 --set run.duration_s=0.02 --summary "$dir/bus.json" \
    > /dev/null 2>&1
rc=$?
if [ $rc -eq 0 ] && grep -q '"final_state_name": "PWM_CHECK", "final_fault": 0' "$dir/bus.json"; then
    pass "drive_sil CLI level 1 on 12 V: exit 0, PWM_CHECK"
else
    failed "drive_sil CLI level 1 on 12 V: exit $rc, $(grep -o '"final_state_name": "[A-Z_]*"' "$dir/bus.json")"
fi

[ $fail -eq 0 ] && echo "drive_sil CLI: all passed"
echo "drive_sil CLI: $npass passed, $nfail failed"
exit $fail
