"""The campaign's spec: the [campaign] section of a motor file, its
tolerance distributions with defaults derived from the motor's data, the
draws, and the scenario overrides of one draw.

A draw's inputs depend only on (seed, draw index): each input takes the
uniform number of its own slot of numpy's SeedSequence(seed, spawn_key =
(index,)) and maps it through its distribution's inverse CDF. Slots are
fixed per key (KEYS, append-only), so overriding one distribution leaves
every other input of every draw as it was.
"""
import math
import re
from statistics import NormalDist

import numpy as np

# The rule's allowance and its window where a file names none: one home, rule_check.
from .rule_check import TE_MARGIN_NM as RULE_MARGIN_NM  # noqa: F401 (campaign, campaign_report)
from .rule_check import DEFAULT_WINDOW as RULE_DEFAULT_WINDOW

TWO_PI = 2.0 * math.pi
RPM_PER_RAD_S = 60.0 / TWO_PI
ADC_BITS = 12                       # the F28335's ADC (hal/sim: the current ADC is 12 bit)
SLOT_NOISE_SEED = 0                 # plant.seed of the draw (both methods)
N_SLOTS = 32                        # words drawn per draw; slots >= len(KEYS) + 2 stay spare

# Physics behind the motor-derived defaults (CAMPAIGN_KEYS.md says why each one).
DEADTIME_PER_PERIOD = 0.01          # dead time up to 1 % of the PWM period
DROP_PER_VDC = 0.004                # device drop up to 0.4 % of the bus (1.2 V at 311 V)
NOISE_LSB = 3.0                     # ADC noise up to 3 LSB (std dev)
OFFSET_LSB = 4.0                    # ADC offset std dev, uncalibrated
ENC_MOUNT_MECH_DEG = 0.5            # encoder offset error std dev, mechanical degrees
RAMP_TORQUE_PER_RATED = 0.25        # ramps accelerate J with a quarter of T_rated
START_MARGIN_S = 0.05               # the drawn point starts this long after step 1, rounded up
TIME_GRID_S = 0.01                  # ramp_s rounded up to this
START_GRID_S = 0.1                  # start_s rounded up to this
LOAD_STEP_FROM = 0.2                # load_step: this x the drawn load before the event
SPEED_STEP_FROM = 0.5               # speed_step: this x the drawn speed before the event

CORNER_U = 1e-9                     # the corner draws' uniform number (6 sigma of a normal)

TRANSIENTS = ("none", "load_step", "speed_step")
DISTS = ("fixed", "uniform", "loguniform", "normal", "lognormal", "choice")


class SpecError(ValueError):
    """A [campaign] key or the motor file cannot make a campaign: the message names it."""


class Key:
    """One [campaign] key. A distribution draws one value per slot into the columns named (slots
    fixed forever: a new key takes new slots); a timeline setting has no slot. default(m) is the
    default's text for the motor m (motor_data()), doc its form in the key list."""

    def __init__(self, name, domain, meaning, default, doc=None, slots=(), columns=None):
        self.name, self.domain, self.meaning, self.slots = name, domain, meaning, slots
        self.default = default if callable(default) else (lambda m, d=default: d)
        self.doc = doc if doc is not None else default
        self.columns = columns or ((name,) if slots else ())


def _lsb(m):
    """One LSB of the 12-bit current ADC [A]."""
    return 2.0 * m["adc_full_scale_A"] / 2 ** ADC_BITS


KEYS = [
    Key("R_factor", "positive", "controller's R / plant's R: the datasheet's 20 C value against a winding up "
        "to 100 K warmer (copper +0.39 %/K: x 1/1.39) and a +-10 % tolerance", "loguniform 0.65 1.1", slots=(1,)),
    Key("L_factor", "positive", "controller's L / plant's L: datasheet tolerance and saturation (L falls "
        "with current)", "loguniform 0.7 1.4", slots=(2,)),
    Key("psif_factor", "positive", "controller's psi_f / plant's: magnets up to 100 K warmer than the "
        "datasheet's (NdFeB -0.12 %/K: x 1/0.88) and a +-5 % tolerance", "uniform 0.95 1.19", slots=(3,)),
    Key("J_factor", "positive", "controller's J / plant's J: the load's inertia known to a factor of 2 "
        "(the speed gains follow it unless the file sets them)", "loguniform 0.5 2", slots=(4,)),
    Key("deadtime_s", "nonneg", "plant's dead time [s]: up to 1 % of the PWM period (1 us at 10 kHz)",
        lambda m: f"uniform 0 {DEADTIME_PER_PERIOD * m['Ts_s']:.4g}", "uniform 0 (0.01 x PWM period)",
        slots=(5,)),
    Key("deadtime_comp", "fraction", "controller's dead time / plant's: how much of it the drive "
        "compensates", "uniform 0 1", slots=(6,)),
    Key("device_drop_V", "nonneg", "on-state drop of the conducting device [V]: up to 0.4 % of the bus "
        "(1.2 V at 311 V)", lambda m: f"uniform 0 {DROP_PER_VDC * m['vdc_V']:.4g}", "uniform 0 (0.004 x vdc_V)",
        slots=(7,)),
    Key("adc_noise_A", "nonneg", "current ADC noise, std dev [A]: up to 3 LSB of the 12-bit ADC",
        lambda m: f"uniform 0 {NOISE_LSB * _lsb(m):.4g}", "uniform 0 (3 LSB = 3 x 2 adc_full_scale_A / 4096)",
        slots=(8,)),
    Key("adc_offset_A", "any", "offset of each current channel [A], a and b drawn apart: uncalibrated "
        "(run.calibrate = on measures it away)", lambda m: f"normal 0 {OFFSET_LSB * _lsb(m):.4g}",
        "normal 0 (4 LSB)", slots=(9, 10), columns=("adc_offset_a_A", "adc_offset_b_A")),
    Key("encoder_offset_err_el_rad", "any", "controller's encoder offset - plant's [rad el]: a 0.5 "
        "mechanical degree mounting tolerance (run.align = on measures it instead)",
        lambda m: f"normal 0 {m['pole_pairs'] * math.radians(ENC_MOUNT_MECH_DEG):.4g}",
        "normal 0 (0.5 mech. deg x pole_pairs)", slots=(11,)),
    Key("encoder_lines", "lines", "encoder lines (x4 counts): the common incremental encoders",
        "choice 1000 2048 2500 4096", slots=(12,)),
    Key("vdc_factor", "positive", "bus / the file's vdc_V: mains +-10 %", "uniform 0.9 1.1", slots=(13,)),
    Key("speed_frac", "positive", "operating speed / n_rated_rpm", "uniform 0.1 0.9", slots=(14,)),
    Key("load_frac", "nonneg", "load torque / T_rated (T_rated = 1.5 pole_pairs psif_Wb i_rated_A)",
        "uniform 0.1 1", slots=(15,)),
    Key("transient", "transient", "the event: none, load_step (the load 0.2 x the drawn one before it), "
        "speed_step (a reference step from 0.5 x the drawn speed)", "choice none load_step speed_step",
        slots=(16,)),
    Key("timeline", "timeline", "drawn: the file's start-up until start_s, then the drawn operating point "
        "and transient; file: the file's [reference], [load] and run as they are (tolerances drawn only)",
        "drawn"),
    Key("start_s", "time", "drawn: when the drawn point takes over [s]; the proposed method's step 1 has "
        "ended by then in a run of the file as it is",
        lambda m: (f"{_ceil(m['t_run_s'] + START_MARGIN_S, START_GRID_S):g}" if m["t_run_s"] is not None
                   else "unknown (a run of the file as it is never reaches RUN)"),
        "the file's step 1 end + 0.05 s, rounded up to 0.1 s"),
    Key("ramp_s", "time", "drawn: the speed ramps to the drawn point in this time [s]",
        lambda m: f"{_ceil(m['J_kgm2'] * m['n_rated_rpm'] / RPM_PER_RAD_S / (RAMP_TORQUE_PER_RATED * m['T_rated_Nm']), TIME_GRID_S):g}",
        "J n_rated / (0.25 T_rated), rounded up to 0.01 s"),
    Key("settle_s", "time", "drawn: from the ramp's end to the event [s]", "0.3"),
    Key("recover_s", "time", "drawn: from the event + ramp_s to the judged window [s]", "0.3"),
    Key("window_s", "time", "drawn: the judged window's length [s]", "0.2"),
    Key("window", "window", "file: the judged window T0:T1 [s]", lambda m: m["file_window"],
        "the file's `; win steady`, else `; win late`, else 0.8:1.2"),
]
KEY_BY_NAME = {k.name: k for k in KEYS}
# The keys only one timeline reads (the other leaves them out, its draws' columns null).
TIMELINE_ONLY = {"drawn": ("speed_frac", "load_frac", "transient", "start_s", "ramp_s", "settle_s", "recover_s",
                           "window_s"),
                 "file": ("window",)}
OPERATING_COLUMNS = ("speed_frac", "load_frac", "transient", "speed_rpm", "load_Nm")
DIST_KEYS = [k for k in KEYS if k.slots]
INPUT_COLUMNS = [c for k in DIST_KEYS for c in k.columns]


def _ceil(x, grid):
    """x rounded up to the grid (and a tidy decimal)."""
    return round(math.ceil(x / grid - 1e-9) * grid, 10)


# ---- distributions -----------------------------------------------------------------------------

class Dist:
    """One distribution, parsed from its text ("uniform 0 1e-6", "choice a b", "1.2")."""

    def __init__(self, text, domain):
        self.text = " ".join(text.split())
        words = self.text.split()
        if not words:
            raise SpecError("no value (expected a distribution: " + ", ".join(DISTS) + ")")
        if len(words) == 1 and words[0] not in DISTS:
            words = ["fixed"] + words
        self.kind, args = words[0], words[1:]
        if self.kind not in DISTS:
            raise SpecError(f"unknown distribution \"{self.kind}\" (one of: {', '.join(DISTS)})")
        if domain == "transient":
            if self.kind not in ("fixed", "choice"):
                raise SpecError(f"{self.kind}: the transient is fixed NAME or choice NAME... "
                                f"({', '.join(TRANSIENTS)})")
            bad = [a for a in args if a not in TRANSIENTS]
            if bad or not args:
                raise SpecError(f"unknown transient \"{(bad or [''])[0]}\" (one of: {', '.join(TRANSIENTS)})")
            self.values = args
            return
        self.values = [self._number(a) for a in args]
        need = {"fixed": 1, "uniform": 2, "loguniform": 2, "normal": 2, "lognormal": 2}.get(self.kind)
        if need is not None and len(self.values) != need:
            raise SpecError(f"{self.kind} takes {need} number{'s' if need > 1 else ''}, got {len(args)}")
        if self.kind == "choice" and not self.values:
            raise SpecError("choice takes one value or more")
        v = self.values
        if self.kind in ("uniform", "loguniform") and not v[0] <= v[1]:
            raise SpecError(f"{self.kind} {v[0]:g} {v[1]:g}: the low end above the high end")
        if self.kind == "loguniform" and not v[0] > 0:
            raise SpecError(f"loguniform {v[0]:g} {v[1]:g}: the ends must be > 0")
        if self.kind == "normal" and not v[1] >= 0:
            raise SpecError(f"normal {v[0]:g} {v[1]:g}: the standard deviation must be >= 0")
        if self.kind == "lognormal" and not (v[0] > 0 and v[1] >= 1):
            raise SpecError(f"lognormal {v[0]:g} {v[1]:g}: MEDIAN > 0 and the geometric std dev GSD >= 1")
        self._check_domain(domain)

    @staticmethod
    def _number(word):
        try:
            x = float(word)
        except ValueError:
            raise SpecError(f"\"{word}\" is not a number") from None
        if not math.isfinite(x):
            raise SpecError(f"\"{word}\" is not a finite number")
        return x

    def support(self):
        """(low, high) of the values the distribution can take."""
        v = self.values
        if self.kind in ("fixed", "choice"):
            return min(v), max(v)
        if self.kind in ("uniform", "loguniform"):
            return v[0], v[1]
        if self.kind == "lognormal":
            return (0.0, math.inf) if v[1] > 1 else (v[0], v[0])
        return (-math.inf, math.inf) if v[1] > 0 else (v[0], v[0])

    def _check_domain(self, domain):
        lo, hi = self.support()
        if domain == "positive" and not lo > 0 and not (self.kind == "lognormal"):
            raise SpecError(f"{self.text}: takes values <= 0 (this key is a ratio > 0; lognormal or "
                            f"loguniform keep it positive)")
        if domain == "nonneg" and not lo >= 0:
            raise SpecError(f"{self.text}: takes values < 0 (this key is >= 0)")
        if domain == "fraction" and not (lo >= 0 and hi <= 1):
            raise SpecError(f"{self.text}: takes values outside 0..1 (this key is a fraction)")
        if domain == "lines":
            if self.kind not in ("fixed", "choice"):
                raise SpecError(f"{self.text}: encoder lines are whole: fixed N or choice N...")
            if any(x != math.floor(x) or not 1 <= x <= 1e6 for x in self.values):
                raise SpecError(f"{self.text}: encoder lines are whole numbers 1 .. 1e6")

    def value(self, u):
        """The value at the uniform number u in (0, 1): the inverse CDF."""
        v = self.values
        if self.kind == "fixed":
            return v[0]
        if self.kind == "choice":
            return v[min(int(u * len(v)), len(v) - 1)]
        if self.kind == "uniform":
            return v[0] + u * (v[1] - v[0])
        if self.kind == "loguniform":
            return math.exp(math.log(v[0]) + u * (math.log(v[1]) - math.log(v[0])))
        z = NormalDist().inv_cdf(u)
        if self.kind == "normal":
            return v[0] + v[1] * z
        return v[0] * v[1] ** z


def uniforms(seed, index):
    """The draw's uniform numbers in (0, 1), one per slot (numpy's SeedSequence, 53 bits each)."""
    words = np.random.SeedSequence(seed, spawn_key=(index,)).generate_state(N_SLOTS, np.uint64)
    return [((int(w) >> 11) + 0.5) / 2.0 ** 53 for w in words], [int(w) for w in words]


# ---- the [campaign] section and the file's windows -----------------------------------------------

SECTION_RE = re.compile(r"^\s*\[([^\]]*)\]")
KEY_RE = re.compile(r"^([A-Za-z_][A-Za-z0-9_]*)\s*[=:]\s*(.*)$")
WIN_RE = re.compile(r"^;\s*win\s+(steady|late)\s*=\s*([0-9.eE+-]+)\s*:\s*([0-9.eE+-]+)\s*$")


def _strip_comment(value):
    """An inline comment (; or # after a blank) off a value."""
    m = re.search(r"\s[;#]", value)
    return (value[:m.start()] if m else value).strip()


def read_campaign_section(path, text):
    """{key: (text, line)} of text's [campaign] section(s); SpecError names FILE:LINE on a bad line."""
    out = {}
    section = None
    last = None
    for n, line in enumerate(text.splitlines(), 1):
        m = SECTION_RE.match(line)
        if m:
            section, last = m.group(1).strip(), None
            continue
        if section != "campaign" or not line.strip() or line.lstrip()[0] in ";#":
            continue
        if line[0] in " \t" and last is not None:        # a continuation line
            value, at = out[last]
            out[last] = (value + " " + _strip_comment(line), at)
            continue
        km = KEY_RE.match(line.strip())
        if not km:
            raise SpecError(f"{path}:{n}: [campaign]: expected key = distribution")
        key, value = km.group(1), _strip_comment(km.group(2))
        if key not in KEY_BY_NAME:
            raise SpecError(f"{path}:{n}: [campaign] {key}: unknown key (one of: {', '.join(KEY_BY_NAME)})")
        if key in out:
            raise SpecError(f"{path}:{n}: [campaign] {key}: given twice (first at line {out[key][1]})")
        out[key], last = (value, n), key
    return out


def check_section(path, text):
    """The [campaign] section's keys and the distributions it gives, checked without the motor's
    data (so its mistakes are named before any run); SpecError."""
    for name, (value, line) in read_campaign_section(path, text).items():
        k = KEY_BY_NAME[name]
        if k.slots:
            try:
                Dist(value, k.domain)
            except SpecError as e:
                raise SpecError(f"{path}:{line}: [campaign] {name}: {e}") from None


def file_window(text):
    """The judged window a scenario file names: `; win steady`, else `; win late`, else the rule's default."""
    found = {}
    for line in text.splitlines():
        m = WIN_RE.match(line.strip())
        if m:
            found.setdefault(m.group(1), f"{float(m.group(2)):g}:{float(m.group(3)):g}")
    return found.get("steady", found.get("late", RULE_DEFAULT_WINDOW))


def parse_window(text):
    """(t0, t1) of "T0:T1", SpecError unless 0 <= T0 < T1."""
    try:
        t0, t1 = (float(x) for x in text.split(":"))
    except ValueError:
        raise SpecError(f"\"{text}\": expected T0:T1 in seconds") from None
    if not (math.isfinite(t0) and math.isfinite(t1) and 0 <= t0 < t1):
        raise SpecError(f"\"{text}\": expected 0 <= T0 < T1")
    return t0, t1


def _time(text):
    try:
        x = float(text)
    except ValueError:
        raise SpecError(f"\"{text}\" is not a number of seconds") from None
    if not (math.isfinite(x) and x >= 0):
        raise SpecError(f"\"{text}\": a time >= 0 [s]")
    return x


# ---- the spec --------------------------------------------------------------------------------------

class Spec:
    """The campaign's distributions and timeline for one motor (motor_data()), from its file's
    [campaign] section over the defaults. as_dict() is what campaign.json records."""

    def __init__(self, path, text, motor):
        self.motor = motor
        given = read_campaign_section(path, text)
        self.text, self.source = {}, {}
        for k in KEYS:
            if k.name in given:
                self.text[k.name], self.source[k.name] = given[k.name][0], f"{path}:{given[k.name][1]}"
            else:
                self.text[k.name], self.source[k.name] = k.default(motor), "default"
        self.dists = {}
        for k in DIST_KEYS:
            self.dists[k.name] = self._parse(k.name, lambda t, k=k: Dist(t, k.domain))
        self.timeline = self._parse("timeline", _timeline)
        if self.timeline == "drawn":
            if motor["mode"] != "speed":
                raise SpecError(f"{self._where('timeline')}: drawn runs the speed loop; the file's "
                                f"[controller] mode is {motor['mode']} (set timeline = file)")
            self.start_s = self._parse("start_s", _time)
            self.ramp_s = self._parse("ramp_s", _positive_time)
            self.settle_s = self._parse("settle_s", _positive_time)
            self.recover_s = self._parse("recover_s", _time)
            self.window_s = self._parse("window_s", _positive_time)
            self.event_s = _round(self.start_s + self.ramp_s + self.settle_s)
            t0 = _round(self.event_s + self.ramp_s + self.recover_s)
            self.duration_s = _round(t0 + self.window_s)
            self.window = f"{t0:g}:{self.duration_s:g}"
        else:
            self.window = self._parse("window", lambda t: _window_in(t, motor["duration_s"]))

    def _where(self, name):
        src = self.source[name]
        return f"[campaign] {name} (default)" if src == "default" else f"{src}: [campaign] {name}"

    def _parse(self, name, fn):
        try:
            return fn(self.text[name].strip())
        except SpecError as e:
            raise SpecError(f"{self._where(name)}: {e}") from None

    def as_dict(self):
        return {"keys": dict(self.text), "window": self.window}

    # -- one draw --

    def inputs(self, seed, index):
        """The draw's inputs (a dict, physical units) from (seed, index) alone."""
        u, words = uniforms(seed, index)
        return self.inputs_at(u, words[SLOT_NOISE_SEED])

    def corner(self, u):
        """The inputs with every uniform number at u, a choice's values sorted: CORNER_U and
        1 - CORNER_U bound the values a campaign can draw (a normal's to 6 standard deviations)."""
        return self.inputs_at([u] * N_SLOTS, 1, sort_choices=True)

    def inputs_at(self, u, noise_word, sort_choices=False):
        """The inputs of the uniform numbers u (one per slot) and the noise seed's word."""
        m = self.motor
        x = {}
        for k in DIST_KEYS:
            d = self.dists[k.name]
            for slot, col in zip(k.slots, k.columns):
                if sort_choices and d.kind == "choice":
                    x[col] = sorted(d.values)[-1 if u[slot] > 0.5 else 0]
                else:
                    x[col] = d.value(u[slot])
        x["encoder_lines"] = int(x["encoder_lines"])
        x["noise_seed"] = noise_word & 0xFFFFFFFF
        x["vdc_V"] = x["vdc_factor"] * m["vdc_V"]
        x["speed_rpm"] = x["speed_frac"] * m["n_rated_rpm"]
        x["load_Nm"] = x["load_frac"] * m["T_rated_Nm"]
        if self.timeline == "file":
            x.update({c: None for c in OPERATING_COLUMNS})
        return x

    def keys_in_use(self):
        """The keys this spec reads (the other timeline's left out)."""
        other = TIMELINE_ONLY["file" if self.timeline == "drawn" else "drawn"]
        return [k for k in KEYS if k.name not in other]

    def overrides(self, x):
        """The draw's scenario overrides ("section.key=value"), the same for both methods."""
        m = self.motor
        sets = [f"plant.deadtime_s={_num(x['deadtime_s'])}",
                f"controller.deadtime_s={_num(x['deadtime_comp'] * x['deadtime_s'])}",
                f"plant.device_drop_V={_num(x['device_drop_V'])}",
                f"plant.adc_noise_A={_num(x['adc_noise_A'])}",
                f"plant.adc_offset_a_A={_num(x['adc_offset_a_A'])}",
                f"plant.adc_offset_b_A={_num(x['adc_offset_b_A'])}",
                f"plant.encoder_lines={x['encoder_lines']}",
                f"controller.encoder_offset_el_rad="
                f"{_num(m['encoder_offset_el_rad'] + x['encoder_offset_err_el_rad'])}",
                f"plant.vdc_V={_num(x['vdc_V'])}",
                f"plant.seed={x['noise_seed']}",
                f"controller.J_kgm2={_num(x['J_factor'] * m['J_kgm2'])}"]
        for name, plant in (("R", "R_ohm"), ("L", "L_H"), ("psif", "psif_Wb")):
            f = x[f"{name}_factor"]
            if m["told_absolute"][plant]:     # the file tells the value itself: keep its key
                sets.append(f"controller.{plant}={_num(f * m[plant])}")
            else:
                sets.append(f"controller.{name}_factor={_num(f)}")
        if self.timeline == "drawn":
            sets += self._timeline_sets(x)
        return sets

    def _timeline_sets(self, x):
        m = self.motor
        t0, t_ev = self.start_s, self.event_s
        n, load = x["speed_rpm"], x["load_Nm"]
        n_before = SPEED_STEP_FROM * n if x["transient"] == "speed_step" else n
        load_before = LOAD_STEP_FROM * load if x["transient"] == "load_step" else load
        speed = _profile_before(m["speed_profile"], t0)
        speed += [f"{t0:g}:{_num(_profile_eval(m['speed_profile'], t0))}",
                  f"{_round(t0 + self.ramp_s):g}:{_num(n_before)}~"]
        if x["transient"] == "speed_step":
            speed.append(f"{t_ev:g}:{_num(n)}")
        torque = _profile_before(m["load_profile"], t0) + [f"{t0:g}:{_num(load_before)}"]
        if x["transient"] == "load_step":
            torque.append(f"{t_ev:g}:{_num(load)}")
        return ["reference.speed_rpm=" + ", ".join(speed), "load.torque_Nm=" + ", ".join(torque),
                f"run.duration_s={self.duration_s:g}"]


def _timeline(text):
    if text not in ("drawn", "file"):
        raise SpecError(f"\"{text}\" (one of: drawn, file)")
    return text


def _positive_time(text):
    t = _time(text)
    if not t > 0:
        raise SpecError(f"\"{text}\": a time > 0 [s]")
    return t


def _window_in(text, duration_s):
    t0, t1 = parse_window(text)
    if t1 > duration_s + 1e-12:
        raise SpecError(f"{text}: ends after the file's run ({duration_s:g} s)")
    return f"{t0:g}:{t1:g}"


METHODS = {"conv": ["controller.method=conventional", "identify.mode=off"],
           "prop": ["controller.method=proposed"]}
METHOD_NAMES = {"conv": "conventional", "prop": "proposed"}


def _round(t):
    return round(t, 10)


def _num(v):
    """A value as written to drive_sil: the shortest text that reads back as the same double."""
    return repr(float(v))


def _profile_before(points, t):
    """The profile's points before t as text."""
    return [f"{p[0]:.10g}:{p[1]:.10g}{'~' if p[2] else ''}" for p in points if p[0] < t]


def _profile_eval(points, t):
    """A profile's value at t (tools/sil/profile.h: steps, a ramp from the previous point)."""
    v, t_prev, v_prev = 0.0, 0.0, 0.0
    for t_i, v_i, ramp in points:
        if t_i > t:
            if ramp:
                return v_prev + (v_i - v_prev) * (t - t_prev) / (t_i - t_prev)
            return v
        v, t_prev, v_prev = v_i, t_i, v_i
    return v


def motor_data(resolved, nominal, text):
    """What the spec derives from: drive_sil's .resolved.json of the file and the summary of a run of
    the file as it is with the proposed method (its step 1's end, its PWM period)."""
    keys = resolved["keys"]

    def val(name):
        return keys[name]["value"]

    plant_R = val("plant.R_ohm")
    m = {"R_ohm": plant_R[0][1] if isinstance(plant_R, list) else plant_R,
         "L_H": val("plant.L_H"), "psif_Wb": val("plant.psif_Wb"), "pole_pairs": val("plant.pole_pairs"),
         "J_kgm2": val("plant.J_kgm2"), "vdc_V": val("plant.vdc_V"),
         "adc_full_scale_A": val("plant.adc_full_scale_A"),
         "encoder_offset_el_rad": val("plant.encoder_offset_el_rad"),
         "i_rated_A": val("motor.i_rated_A"), "n_rated_rpm": val("motor.n_rated_rpm"),
         "mode": val("controller.mode"), "identify_mode": val("identify.mode"),
         "duration_s": val("run.duration_s"),
         "speed_profile": val("reference.speed_rpm"), "load_profile": val("load.torque_Nm"),
         "told_absolute": {p: keys[f"controller.{p}"]["source"] == "set"
                           for p in ("R_ohm", "L_H", "psif_Wb")},
         "t_run_s": nominal.get("t_run_s"), "Ts_s": m_ts(nominal, val("run.duration_s")),
         "file_window": file_window(text)}
    m["T_rated_Nm"] = 1.5 * m["pole_pairs"] * m["psif_Wb"] * m["i_rated_A"]
    return m


def m_ts(nominal, duration_s):
    """The PWM period of the drive: the nominal run's duration over its periods."""
    return duration_s / nominal["periods"]


def keys_markdown():
    """CAMPAIGN_KEYS.md: every [campaign] key with its default and meaning."""
    out = ["# Campaign keys", "",
           "Generated from `tools/drivekit/drivekit/campaign_spec.py` by `drive-campaign --list-keys",
           "--markdown` (`make campaign-keys` rewrites it; `make test` checks it). A motor file's",
           "`[campaign]` section overrides any of them; drive_sil skips the section. Defaults in",
           "brackets derive from the file's data (drive_sil's resolved values): the report and",
           "`OUT/campaign.json` give them as numbers.", "",
           "Distributions (each input of a draw): `fixed V` (or just `V`), `uniform LO HI`,",
           "`loguniform LO HI` (uniform in log), `normal MEAN SD`, `lognormal MEDIAN GSD`",
           "(GSD the geometric standard deviation, a factor >= 1), `choice A B ...` (each equally",
           "likely; repeat one to weight it).", "",
           "| key | default | meaning |", "| --- | --- | --- |"]
    for k in KEYS:
        out.append(f"| {k.name} | {k.doc} | {k.meaning} |")
    out += ["",
            "The timeline `drawn` (times from the file's start): the file's `[reference]` and `[load]`",
            "until `start_s`; the speed ramps to the drawn point by `start_s + ramp_s`, the load steps",
            "to it at `start_s`; the event at `start_s + ramp_s + settle_s`; the judged window",
            "`window_s` long from the event + `ramp_s + recover_s`; the run ends with it. Each draw",
            "runs both methods on the same inputs: the conventional one with `identify.mode = off`,",
            "the proposed one with the file's step 1."]
    return "\n".join(out) + "\n"
