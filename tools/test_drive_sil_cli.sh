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
sys.exit(0 if d["plant"]["L_H"] == 0.0165 and abs(d["controller"]["L_H"] - 0.00825) < 1e-9 else 1)' "$dir/res.resolved.json"; then
    pass "drive_sil CLI good run: res.resolved.json with the --set plant and controller values"
else
    failed "drive_sil CLI resolved values beside the CSV"
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

[ $fail -eq 0 ] && echo "drive_sil CLI: all passed"
echo "drive_sil CLI: $npass passed, $nfail failed"
exit $fail
