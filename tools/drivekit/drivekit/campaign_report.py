"""A campaign's report (OUT/report.md, its PNGs) and reproducers (OUT/worst/*.ini)
from its results table: the rule's pass rate, the advantage conv/prop, the
worst draws, the inputs that go with failures, the spec and the drive's
version."""
import math
import os
import re
import shutil

import numpy as np

from . import campaign_spec as cs

SIGNED = ("adc_offset_a_A", "adc_offset_b_A", "encoder_offset_err_el_rad")   # ranked by magnitude
EARNS = 2.0                         # conv/prop at which the proposed method earns its place (advantage/)
LINE_MAX = 150                      # reproducer lines longer than this continue on indented lines
Z95 = 1.959964                      # the normal quantile of a 95 % interval


# ---- statistics ---------------------------------------------------------------------------------

def wilson(k, n):
    """95 % Wilson interval of a proportion k/n, in %."""
    if n == 0:
        return math.nan, math.nan
    p, z2 = k / n, Z95 ** 2
    c = (p + z2 / (2 * n)) / (1 + z2 / n)
    h = Z95 * math.sqrt(p * (1 - p) / n + z2 / (4 * n * n)) / (1 + z2 / n)
    return 100 * (c - h), 100 * (c + h)


def ranks(v):
    """Ranks 1..n of v, ties sharing their mean rank."""
    v = np.asarray(v, dtype=float)
    uniq, inv, counts = np.unique(v, return_inverse=True, return_counts=True)
    start = np.concatenate(([0], np.cumsum(counts)[:-1]))
    return (start + (counts + 1) / 2.0)[inv]


def spearman(x, y):
    """Spearman's rank correlation of x and y (NaN when either is constant or n < 3)."""
    if len(x) < 3:
        return math.nan
    rx, ry = ranks(x), ranks(y)
    sx, sy = rx.std(), ry.std()
    if sx == 0 or sy == 0:
        return math.nan
    return float(((rx - rx.mean()) * (ry - ry.mean())).mean() / (sx * sy))


def auc(x, positive):
    """P(x of a positive draw > x of a negative one), ties halved (Mann-Whitney U / n1 n0)."""
    positive = np.asarray(positive, dtype=bool)
    n1, n0 = int(positive.sum()), int((~positive).sum())
    if n1 == 0 or n0 == 0:
        return math.nan
    r = ranks(x)
    return float((r[positive].sum() - n1 * (n1 + 1) / 2.0) / (n1 * n0))


# ---- the table as columns -----------------------------------------------------------------------

class Results:
    def __init__(self, table):
        self.c = table.to_pydict()
        self.n = table.num_rows

    def col(self, name):
        return self.c[name]

    def arr(self, name):
        return np.array([math.nan if v is None else v for v in self.c[name]], dtype=float)

    def faulted(self, m, i):
        return self.c[f"fault_{m}"][i] not in (None, "NONE")


def tally(r):
    """Counts of the rule's outcomes."""
    ok, why = r.col("rule_ok"), r.col("rule_why")
    t = {"held": sum(1 for v in ok if v is True),
         "worse": sum(1 for v, e in zip(ok, r.col("excess_Nm")) if v is False and e is not None),
         "trips": sum(1 for v, e in zip(ok, r.col("excess_Nm")) if v is False and e is None),
         "both_trip": sum(1 for w in why if w == "both trip"),
         "conv_trips": sum(1 for w in why if w == "conventional trips"),
         "errors": sum(1 for i in range(r.n) if r.col("error_conv")[i] or r.col("error_prop")[i]),
         "unmeasured": sum(1 for v, w in zip(ok, why) if v is None and w == "no rows in the window")}
    t["judged"] = r.n - t["errors"] - t["unmeasured"]
    t["held_pct"] = 100.0 * t["held"] / t["judged"] if t["judged"] else math.nan
    t["lo_pct"], t["hi_pct"] = wilson(t["held"], t["judged"])
    adv = np.array([v for v in r.col("advantage") if v is not None and math.isfinite(v)], dtype=float)
    t["adv"] = adv
    if len(adv):
        q1, med, q3 = np.percentile(adv, [25, 50, 75])
        t.update(adv_median=float(med), adv_q1=float(q1), adv_q3=float(q3),
                 adv_earns_pct=100.0 * float((adv >= EARNS).mean()), adv_below1_pct=100.0 * float((adv < 1).mean()))
        t["adv_median_text"] = f"{med:.2f}"
    else:
        t["adv_median_text"] = "n/a"
    return t


def sensitivity(r):
    """[(input label, rho with the excess, rho with log advantage, AUC of failures, fail median, all
    median)] sorted by how well each input goes with failures (|AUC - 0.5|, else |rho excess|)."""
    excess, adv = r.arr("excess_Nm"), r.arr("advantage")
    fail = np.array([v is False for v in r.col("rule_ok")])
    judged = np.array([v is not None for v in r.col("rule_ok")])
    out = []
    for c in cs.INPUT_COLUMNS:
        if c == "transient":
            continue
        x = r.arr(c)
        label = c
        if c in SIGNED:
            x, label = np.abs(x), f"|{c}|"
        if not np.isfinite(x).any() or np.nanstd(x) == 0:
            continue
        ok_e, ok_a = np.isfinite(excess), np.isfinite(adv) & (adv > 0)
        rho_e = spearman(x[ok_e], excess[ok_e])
        rho_a = spearman(x[ok_a], np.log(adv[ok_a]))
        a = auc(x[judged], fail[judged])
        fmed = float(np.median(x[fail])) if fail.any() else math.nan
        out.append((label, rho_e, rho_a, a, fmed, float(np.median(x))))

    def key(t):
        a = 0.0 if math.isnan(t[3]) else abs(t[3] - 0.5)
        e = 0.0 if math.isnan(t[1]) else abs(t[1])
        return (-a, -e) if fail.any() else (-e,)
    return sorted(out, key=key)


def by_transient(r):
    rows = []
    tr, ok, ex = r.col("transient"), r.col("rule_ok"), r.arr("excess_Nm")
    for name in sorted(set(tr) - {None}):
        idx = [i for i in range(r.n) if tr[i] == name]
        judged = [i for i in idx if ok[i] is not None]
        held = sum(1 for i in judged if ok[i])
        e = ex[idx]
        e = e[np.isfinite(e)]
        rows.append((name, len(idx), held, len(judged), float(np.median(e)) if len(e) else math.nan))
    return rows


# ---- worst draws and their reproducers ----------------------------------------------------------

def worst(r, m, k):
    """The k worst draws of method m: tripped ones first, then by mean |Te - Te*|."""
    te = r.arr(f"te_err_{m}_Nm")
    order = sorted((i for i in range(r.n) if not r.col(f"error_{m}")[i]),
                   key=lambda i: (not r.faulted(m, i), -(te[i] if math.isfinite(te[i]) else -1.0)))
    return order[:k]


def breakers(r, k):
    """The k draws that break the rule worst: the proposed method tripping alone first."""
    ex = r.arr("excess_Nm")
    idx = [i for i in range(r.n) if r.col("rule_ok")[i] is False]
    return sorted(idx, key=lambda i: (math.isfinite(ex[i]), -ex[i] if math.isfinite(ex[i]) else 0.0))[:k]


def _continued(key, value):
    """key = value, a long profile split on ", " into indented continuation lines (whole points)."""
    line = f"{key} = {value}"
    if len(line) <= LINE_MAX or ", " not in value:
        return [line]
    out, cur = [], f"{key} ="
    for p in value.split(", "):
        if len(cur) + len(p) + 2 > LINE_MAX and not cur.endswith("="):
            out.append(cur)
            cur = "   "
        cur += f" {p}" if cur.endswith("=") or cur.strip() == "" else f", {p}"
    out.append(cur)
    return out


SECTION_LINE = re.compile(r"^\s*\[([^\]]*)\]")


def scenario_with(text, sets):
    """text with its [campaign] section and judged `; win` comments dropped and the overrides
    ("section.key=value") written in (a key's old lines, continuations included, replaced)."""
    blocks = [[None, []]]
    for line in text.splitlines():
        m = SECTION_LINE.match(line)
        if m:
            blocks.append([m.group(1).strip(), [line]])
        elif not cs.WIN_RE.match(line.strip()):
            blocks[-1][1].append(line)
    blocks = [b for b in blocks if b[0] != "campaign"]
    for s in sets:
        left, value = s.split("=", 1)
        section, key = left.split(".", 1)
        block = next((b for b in blocks if b[0] == section), None)
        if block is None:
            block = [section, ["", f"[{section}]"]]
            blocks.append(block)
        lines, kept, at, in_key = block[1], [], None, False
        key_re = re.compile(rf"^{re.escape(key)}\s*[=:]")
        for line in lines:
            stripped = line.strip()
            continuation = line[:1] in (" ", "\t") and stripped and stripped[0] not in ";#"
            if in_key and continuation:
                continue
            in_key = bool(key_re.match(line))
            if in_key:
                at = len(kept) if at is None else at
                continue
            kept.append(line)
        if at is None:
            at = len(kept)
            while at > 1 and not kept[at - 1].strip():
                at -= 1
        block[1] = kept[:at] + _continued(key, value) + kept[at:]
    return "\n".join(line for b in blocks for line in b[1]) + "\n"


def reproducer(plan, draw, m, row):
    """The scenario file of draw `draw` with method m, its figure in its comments."""
    spec, seed = plan["spec"], plan["seed"]
    x = spec.inputs(seed, draw)
    te = row[f"te_err_{m}_Nm"]
    te_text = "nan" if te is None else f"{te:.9g}"
    head = [f"; drive-campaign reproducer: draw {draw}, {cs.METHOD_NAMES[m]} method",
            f"; campaign: seed {seed} on {plan['ident']['motor']} ({plan['version']})",
            *_wrapped("; inputs: ", [f"{c} = {_fmt(x[c])}" for c in cs.INPUT_COLUMNS]),
            f"; final state {row[f'state_{m}']}, fault {row[f'fault_{m}']}",
            f"; win steady = {spec.window}",
            f"; te_err_Nm = {te_text}",
            "; the motor file with the draw's values written in:"]
    return "\n".join(head) + "\n" + scenario_with(plan["text"], spec.overrides(x) + cs.METHODS[m])


def _wrapped(first, items):
    """Comment lines of comma-separated items, none longer than LINE_MAX."""
    out, cur = [], first
    for it in items:
        if len(cur) + len(it) + 2 > LINE_MAX and cur != first:
            out.append(cur.rstrip())
            cur = ";   "
        cur += it + ", "
    out.append(cur.rstrip(", "))
    return out


def _fmt(v):
    return f"{v:.4g}" if isinstance(v, float) else str(v)


def write_worst(out, r, plan, k):
    """OUT/worst/: both methods' reproducers of the k worst draws of each method and of the k draws
    breaking the rule worst; {draw: file stem}."""
    picked = []
    for i in worst(r, "conv", k) + worst(r, "prop", k) + breakers(r, k):
        if i not in picked:
            picked.append(i)
    tmp = os.path.join(out, "worst.tmp")
    shutil.rmtree(tmp, ignore_errors=True)
    os.makedirs(tmp)
    stems = {}
    for i in picked:
        d = r.col("draw")[i]
        row = {key: r.c[key][i] for key in r.c}
        stems[d] = f"draw{d:06d}"
        for m in cs.METHODS:
            with open(os.path.join(tmp, f"{stems[d]}_{m}.ini"), "w") as f:
                f.write(reproducer(plan, d, m, row))
    final = os.path.join(out, "worst")
    shutil.rmtree(final, ignore_errors=True)
    os.replace(tmp, final)
    return stems


# ---- figures ------------------------------------------------------------------------------------

def figures(out, r, t, sens):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    conv, prop = r.arr("te_err_conv_Nm"), r.arr("te_err_prop_Nm")
    ok = r.col("rule_ok")
    fig, ax = plt.subplots(1, 2, figsize=(11, 4.3))
    floor = 1e-4
    both = [i for i in range(r.n) if not r.faulted("conv", i) and not r.faulted("prop", i)
            and math.isfinite(conv[i]) and math.isfinite(prop[i])]
    for sel, style, label in (([i for i in both if ok[i]], dict(c="tab:blue", s=12), "rule held"),
                              ([i for i in both if ok[i] is False], dict(c="tab:red", s=22), "proposed worse")):
        if sel:
            ax[0].scatter(np.maximum(conv[sel], floor), np.maximum(prop[sel], floor), label=label, **style)
    vals = np.concatenate([conv[both], prop[both]]) if both else np.array([1e-3, 1.0])
    lim = [max(floor, np.nanmin(vals) / 2), max(1e-2, np.nanmax(vals) * 2)]
    xs = np.logspace(math.log10(lim[0]), math.log10(lim[1]), 100)
    ax[0].plot(xs, xs + cs.RULE_MARGIN_NM, "r--", lw=1, label="conventional + 0.005 N m (the rule)")
    ax[0].plot(xs, xs / EARNS, "g:", lw=1, label="conventional / 2")
    ax[0].set(xscale="log", yscale="log", xlim=lim, ylim=lim, xlabel="conventional: mean |Te - Te*| [N m]",
              ylabel="proposed: mean |Te - Te*| [N m]",
              title=f"{r.n} draws: rule held in {t['held']} ({t['held_pct']:.1f} %)")
    trips = t["trips"] + t["both_trip"] + t["conv_trips"]
    if trips:
        ax[0].text(0.02, 0.97, f"trips: proposed alone {t['trips']}, conventional alone {t['conv_trips']}, "
                   f"both {t['both_trip']}", transform=ax[0].transAxes, va="top", fontsize=8)
    ax[0].legend(fontsize=8, loc="lower right")
    adv = t["adv"]
    if len(adv):
        bins = np.logspace(math.log10(max(adv.min(), 1e-3)) - 0.05, math.log10(adv.max()) + 0.05, 30)
        ax[1].hist(adv, bins=bins, color="tab:blue")
        ax[1].axvline(1, color="k", lw=1, label="1: a tie")
        ax[1].axvline(EARNS, color="g", ls=":", lw=1, label="2: proposed <= half")
        ax[1].axvline(t["adv_median"], color="tab:orange", lw=1.5, label=f"median {t['adv_median']:.2f}")
        ax[1].set_xscale("log")
        ax[1].legend(fontsize=8)
    ax[1].set(xlabel="advantage: conventional / proposed mean |Te - Te*|", ylabel="draws",
              title="advantage (neither tripped)")
    fig.tight_layout()
    fig.savefig(os.path.join(out, "campaign.png"), dpi=90)
    plt.close(fig)
    fig, ax = plt.subplots(figsize=(7, 0.35 * max(len(sens), 4) + 1))
    labels = [s[0] for s in sens][::-1]
    y = np.arange(len(labels))
    ax.barh(y + 0.2, [0 if math.isnan(s[1]) else s[1] for s in sens][::-1], 0.4,
            label="rank correlation with proposed - conventional")
    ax.barh(y - 0.2, [0 if math.isnan(s[3]) else 2 * (s[3] - 0.5) for s in sens][::-1], 0.4,
            label=f"2 (AUC - 0.5) of the {int(sum(v is False for v in r.col('rule_ok')))} draws breaking the rule")
    ax.set_yticks(y, labels, fontsize=8)
    ax.axvline(0, color="k", lw=0.8)
    ax.set(xlim=(-1, 1), xlabel="> 0: larger input, proposed worse (or failing)", title="what goes with failures")
    ax.legend(fontsize=7, loc="lower right")
    fig.tight_layout()
    fig.savefig(os.path.join(out, "sensitivity.png"), dpi=90)
    plt.close(fig)


# ---- report.md ----------------------------------------------------------------------------------

def _f(v, spec=".4f"):
    return "-" if v is None or (isinstance(v, float) and not math.isfinite(v)) else format(v, spec)


def _fig(row, m):
    if row[f"error_{m}"]:
        return "refused"
    if row[f"fault_{m}"] not in (None, "NONE"):
        return f"trip {row[f'fault_{m}']}"
    return _f(row[f"te_err_{m}_Nm"])


def draw_table(r, idx, stems):
    head = ["| draw | conv [N m] | prop [N m] | rule | transient | speed / n_rated | load / T_rated | R, L, psi_f, J "
            "told x | dead time [us], told x | files |", "| " + " | ".join(["---"] * 10) + " |"]
    for i in idx:
        row = {k: r.c[k][i] for k in r.c}
        d = row["draw"]
        files = f"[conv](worst/{stems[d]}_conv.ini), [prop](worst/{stems[d]}_prop.ini)" if d in stems else ""
        rule = "held" if row["rule_ok"] else ("broken" if row["rule_ok"] is False else "-")
        head.append(f"| {d} | {_fig(row, 'conv')} | {_fig(row, 'prop')} | {rule} {row['rule_why'] or ''} | "
                    f"{row['transient'] or 'the file'} | {_f(row['speed_frac'], '.2f')} | "
                    f"{_f(row['load_frac'], '.2f')} | "
                    f"{row['R_factor']:.2f}, {row['L_factor']:.2f}, {row['psif_factor']:.2f}, "
                    f"{row['J_factor']:.2f} | {1e6 * row['deadtime_s']:.2f}, {row['deadtime_comp']:.2f} | {files} |")
    return head


def _md_intro(n, spec, ident):
    """report.md's title and what a draw runs and the rule judges; each _md_ part ends in a blank line."""
    return [f"# Campaign: {os.path.basename(ident['motor'])}, {n} draws", "",
            f"Motor file `{ident['motor']}`, seed {ident['seed']}, {ident['drive_sil_version']}. Each draw runs "
            "both methods on the same inputs; the rule: the proposed method's mean |Te - Te*| in the judged "
            f"window ({spec.window} s) at most the conventional one's + {cs.RULE_MARGIN_NM} N m, and no trip where "
            "the conventional method does not trip.", ""]


def _md_rule(r, t, stems, k):
    """## The rule: the tally's outcomes, then the k draws breaking it worst (when any does)."""
    L = ["## The rule", "",
         f"**Held in {t['held']} of {t['judged']} judged draws ({_f(t['held_pct'], '.1f')} %, 95 % interval "
         f"{_f(t['lo_pct'], '.1f')}-{_f(t['hi_pct'], '.1f')} %).**", "",
         "| outcome | draws |", "| --- | --- |",
         f"| rule held | {t['held']} |", f"| proposed worse by more than {cs.RULE_MARGIN_NM} N m | {t['worse']} |",
         f"| proposed trips, conventional does not | {t['trips']} |",
         f"| both trip (held) | {t['both_trip']} |", f"| conventional trips alone (held) | {t['conv_trips']} |",
         f"| refused by drive_sil (not judged) | {t['errors']} |",
         f"| no rows in the window (not judged) | {t['unmeasured']} |", ""]
    br = breakers(r, k)
    if br:
        L += [f"The draws breaking the rule worst ({len(br)} of {t['worse'] + t['trips']}):", ""]
        L += draw_table(r, br, stems) + [""]
    return L


def _md_advantage(t):
    """## Advantage: the figure, how to read it, the advantage's quartiles (when a draw has one)."""
    L = ["## Advantage", "", "![campaign](campaign.png)", "",
         "Left: each draw's mean |Te - Te*| of the proposed method over the conventional one's (log "
         "axes; below the red dashed line the rule holds, below the green dotted one the proposed method "
         "halves the conventional error). Right: the advantage conventional / proposed of the draws where "
         "neither method tripped."]
    if "adv_median" in t:
        L += ["", f"Median advantage {t['adv_median']:.2f} (quartiles {t['adv_q1']:.2f}-{t['adv_q3']:.2f}); "
              f"the proposed method at most half the conventional error in {t['adv_earns_pct']:.1f} % of the "
              f"draws, above it (advantage < 1) in {t['adv_below1_pct']:.1f} %."]
    return L + [""]


def _md_worst(r, stems, k):
    """## Worst draws: each method's k worst, and how to run their files under worst/."""
    L = ["## Worst draws", ""]
    for m in cs.METHODS:
        L += [f"The {cs.METHOD_NAMES[m]} method's {k} worst (tripped first):", ""]
        L += draw_table(r, worst(r, m, k), stems) + [""]
    return L + ["Each file under `worst/` is a scenario drive_sil runs as it is: `build/host/drive_sil --scenario "
                "FILE --summary - --window T0:T1` (its `; win steady`) gives its `; te_err_Nm`; "
                "`rule-check worst` (build/venv/bin) judges the pairs.", ""]


def _md_failures(r, t, sens):
    """## What goes with failures: the inputs' correlations and AUC (sens), then the rule by transient."""
    L = ["## What goes with failures", "", "![sensitivity](sensitivity.png)", "",
         "Each input's rank correlation with the proposed method's excess over the conventional one "
         "(proposed - conventional mean |Te - Te*|, draws where neither tripped) and with the log "
         "advantage; where draws break the rule, the AUC: the chance that a failing draw's input is "
         "larger than a passing one's (0.5: no relation; from "
         f"{t['worse'] + t['trips']} failing draws, so read it with their number in mind). Signed inputs by "
         "their magnitude.", "",
         "| input | rho (excess) | rho (log advantage) | AUC (failures) | median, failing | median, all |",
         "| --- | --- | --- | --- | --- | --- |"]
    for s in sens:
        L.append(f"| {s[0]} | {_f(s[1], '+.2f')} | {_f(s[2], '+.2f')} | {_f(s[3], '.2f')} | {_f(s[4], '.4g')} "
                 f"| {_f(s[5], '.4g')} |")
    L += ["", "| transient | draws | rule held | median excess [N m] |", "| --- | --- | --- | --- |"]
    for name, cnt, held, judged, med in by_transient(r):
        L.append(f"| {name} | {cnt} | {held} of {judged} | {_f(med, '+.4f')} |")
    return L + [""]


def _md_campaign(r, spec, ident):
    """## The campaign: the build, files, seed and timeline, the keys in use and the motor's data."""
    absent = [f for f in ("method_ran", "held_share")
              if all(v is None for m in cs.METHODS for v in r.col(f"{f}_{m}"))]
    L = ["## The campaign", "",
         f"drive_sil `{ident['drive_sil_version']}` (sha256 {ident['drive_sil_sha256'][:16]}), motor file "
         f"sha256 {ident['motor_sha256'][:16]}, seed {ident['seed']}, {r.n} draws; the timeline "
         f"`{spec.timeline}`, judged window {spec.window} s."]
    if spec.timeline == "drawn":
        L.append(f"The file's start-up until {spec.start_s:g} s, the drawn point reached by "
                 f"{spec.start_s + spec.ramp_s:g} s, the event at {spec.event_s:g} s, the run ends at "
                 f"{spec.duration_s:g} s.")
    if absent:
        L += ["", f"This drive_sil's summary has no {' or '.join(absent)}: those columns are null in "
              "results.parquet."]
    L += ["", "| key | value | from |", "| --- | --- | --- |"]
    for key in spec.keys_in_use():
        L.append(f"| {key.name} | {spec.text[key.name]} | {spec.source[key.name]} |")
    m = spec.motor
    return L + ["", f"The motor's data used: R {m['R_ohm']:g} ohm, L {m['L_H']:g} H, psi_f {m['psif_Wb']:g} Wb, "
                f"{m['pole_pairs']} pole pairs, J {m['J_kgm2']:g} kg m^2, bus {m['vdc_V']:g} V, i_rated "
                f"{m['i_rated_A']:g} A, n_rated {m['n_rated_rpm']:g} r/min, T_rated {m['T_rated_Nm']:.4g} N m, ADC "
                f"+-{m['adc_full_scale_A']:g} A, PWM period {1e6 * m['Ts_s']:.4g} us. Keys: "
                "`tools/drivekit/CAMPAIGN_KEYS.md`.", ""]


def report_md(r, t, sens, stems, plan, a, k):
    """report.md's text from the results r, their tally t and sensitivity sens, the reproducers' stems
    and the k worst per method (write()'s last step)."""
    spec, ident = plan["spec"], plan["ident"]
    return "\n".join(_md_intro(r.n, spec, ident) + _md_rule(r, t, stems, k) + _md_advantage(t) +
                     _md_worst(r, stems, k) + _md_failures(r, t, sens) + _md_campaign(r, spec, ident))

def write(out, table, plan, a):
    """Figures, reproducers and report.md of the results table; the tally for the closing line."""
    r = Results(table)
    k = int(a.worst)
    t = tally(r)
    sens = sensitivity(r)
    stems = write_worst(out, r, plan, k)
    figures(out, r, t, sens)
    path = os.path.join(out, "report.md")
    with open(path + ".tmp", "w") as f:
        f.write(report_md(r, t, sens, stems, plan, a, k))
    os.replace(path + ".tmp", path)
    return t
