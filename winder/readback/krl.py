"""KUKA KRL read back (the .src, then its .dat; winder.export.dialects.krl writes them): every line one
of the statements below or a comment, anything else refused naming its line (winder.readback.cells).

.src: `&ACCESS RVP`, `&REL 1`, `DEF name( )`, `BAS(#INITMOV, 0)`, `$TOOL = {X,Y,Z,A,B,C}` (the
mandrel's mount) and `$BASE = {...}` (the ring), `$IPO_MODE = #TCP`, `$APO.CDIS = d`, `$VEL_EXTAX[i] =
p` (0 < p <= 100 %), `$VEL.CP = v` (m/s, 0 < v <= MAX_CP), `PTP {A1..A6, E1..E3}` (the start, then
each bridge), `LIN Pn` or `LIN Pn C_DIS`, `END`. .dat: `&ACCESS RVP`, `&REL 1`, `DEFDAT name PUBLIC`,
`DECL E6POS Pn={X,Y,Z,A,B,C,S,T,E1..E6}` (E4-E6 zero), `ENDDAT`. A move's time is the ring centre's
path over $VEL.CP, or where $VEL_EXTAX[1] is below 100 %, E1's travel at that share of its top speed.
A program split per layer (docs/math/10-robot-cell.md 10.10): the main .src calls `<name>_L<N>( )`,
each a module of its own read after it (its .src after the main .src, its .dat after the main .dat:
winder.readback.program_file), each module's body read in place of its call (winder.readback.subprograms).
"""

from __future__ import annotations

import re

import numpy as np

from winder.config.machine import MachineConfig
from winder.errors import ConfigError
from winder.readback.cells import NUMBER, CellRead, Rows, frames_of, number, same_frame, seconds
from winder.readback.subprograms import KRL, defined, in_order

MAX_CP = 3.0  # m/s: KRL's largest path speed
_FRAME_KEYS = ("X", "Y", "Z", "A", "B", "C")
_POINT_KEYS = _FRAME_KEYS + ("S", "T", "E1", "E2", "E3", "E4", "E5", "E6")
_AXES_KEYS = ("A1", "A2", "A3", "A4", "A5", "A6", "E1", "E2", "E3")
_NAME = r"[A-Za-z_][A-Za-z0-9_]{0,23}"
_FIXED = {"&ACCESS RVP", "&REL 1", "BAS(#INITMOV, 0)", "$IPO_MODE = #TCP"}
_DEF = re.compile(rf"^DEF ({_NAME})\( \)$")
_DEFDAT = re.compile(rf"^DEFDAT ({_NAME}) PUBLIC$")
_SET = re.compile(r"^(\$TOOL|\$BASE) = \{(.*)\}$")
_SYSVAR = re.compile(rf"^(\$APO\.CDIS|\$VEL\.CP|\$VEL_EXTAX\[([1-6])\]) = ({NUMBER}|\S.*)$")
_PTP = re.compile(r"^PTP \{(.*)\}$")
_LIN = re.compile(rf"^LIN (P[0-9]{{1,9}})( C_DIS)?$")
_E6POS = re.compile(rf"^DECL E6POS (P[0-9]{{1,9}})=\{{(.*)\}}$")


def _aggregate(body: str, keys: tuple[str, ...], source: str, line: int, what: str) -> list[float]:
    """The values of a KRL aggregate {K v,K v,...} with exactly these keys in this order."""
    parts = [p.split() for p in body.split(",")]
    got = tuple(p[0].upper() if p else "" for p in parts)
    if got != keys or any(len(p) != 2 for p in parts):
        raise ConfigError(f"{source}: line {line}: {what} must list {','.join(keys)} with one number each, got "
                          f"{{{body[:60]}}}")
    return [number(p[1], source, line, f"{what} {p[0]}", -1.0e7, 1.0e7) for p in parts]


def _frame(values: list[float]) -> np.ndarray:
    from scipy.spatial.transform import Rotation  # noqa: PLC0415

    out = np.eye(4)
    out[:3, :3] = Rotation.from_euler("ZYX", values[3:6], degrees=True).as_matrix()
    out[:3, 3] = values[:3]
    return out


def _dat(lines: list[tuple[int, str]], names: list[str], source: str) -> dict[str, list[float]]:
    """The E6POS points of the .dat's lines (number, text): the main module's .dat (names[0]), then
    those of the layers' modules (names[1:], a program split per layer) in that order."""
    points: dict[str, list[float]] = {}
    code = [(n, t.split(";")[0].strip()) for n, t in lines if t.split(";")[0].strip()]
    if not code or code[-1][1] != "ENDDAT":
        raise ConfigError(f"{source}: the .dat does not end with ENDDAT: cut short?")
    left = list(names)
    current = None  # the module whose DEFDAT is open
    for n, line in code:
        hit = _E6POS.match(line)
        if line in ("&ACCESS RVP", "&REL 1") and current is None:
            continue
        if current is None and (m := _DEFDAT.match(line)):
            if not left or m[1].lower() != left[0].lower():
                want = f"{left[0]}'s" if left else "no other (every module's .dat read)"
                raise ConfigError(f"{source}: line {n}: the .dat is {m[1]}'s, the .src wants {want}")
            current = left.pop(0)
        elif line == "ENDDAT" and current is not None:
            current = None
        elif hit and current is not None:
            values = _aggregate(hit[2], _POINT_KEYS, source, n, hit[1])
            if values[6] != int(values[6]) or not 0 <= values[6] <= 7 or values[7] != int(values[7]) or not 0 <= values[7] <= 63:
                raise ConfigError(f"{source}: line {n}: {hit[1]}'s S must be 0-7 and T 0-63, whole numbers")
            if any(values[11:14]):
                raise ConfigError(f"{source}: line {n}: {hit[1]}'s E4-E6 must be 0: the cell has three external axes")
            if hit[1] in points:
                raise ConfigError(f"{source}: line {n}: {hit[1]} is declared twice")
            points[hit[1]] = values
        else:
            raise ConfigError(f"{source}: line {n}: not a statement of winder's KRL data list, got {line[:60]!r}")
    if left:
        raise ConfigError(f"{source}: the .dat of {left[0]} is missing: each module's .dat goes beside its .src")
    return points


def read_krl(text: str, machine: MachineConfig, source: str) -> CellRead:  # noqa: C901, PLR0912, PLR0915
    """The program's rows, frames and ring axes (module docstring)."""
    cell = machine.cell
    all_lines = list(enumerate(text.splitlines(), start=1))
    dat_at = next((k for k, (_, t) in enumerate(all_lines) if t.strip().startswith("DEFDAT")), None)
    if dat_at is None:
        raise ConfigError(f"{source}: a KRL program needs its .dat (DEFDAT ... ENDDAT) beside the .src")
    while dat_at > 0 and all_lines[dat_at - 1][1].strip() in ("&ACCESS RVP", "&REL 1"):
        dat_at -= 1
    rows = Rows.of(source, machine)
    name, ended, start, start_line = None, False, None, 0
    speed, share, mode = np.nan, 100.0, "cp"
    top_e1 = machine.dynamics.rotation.speed / 60.0
    points_lin: list[tuple] = []  # (point, line, mode, $VEL.CP, $VEL_EXTAX[1], pass, kind, tension) of each LIN
    bridges: dict[int, tuple[np.ndarray, int]] = {}
    modules = defined(all_lines[:dat_at], KRL)  # the layers' modules of a program split per layer
    src = in_order(all_lines[:dat_at], KRL, source)  # each layer's subprogram where it is called
    for n, raw in src:
        line = raw.strip()
        if not line or rows.comment(line, n):
            continue
        line = line.split(";")[0].strip()
        if ended:
            raise ConfigError(f"{source}: line {n}: code after END, got {line[:60]!r}")
        if line in _FIXED:
            continue
        if name is None:
            hit = _DEF.match(line)
            if not hit:
                raise ConfigError(f"{source}: line {n}: the .src must start with DEF name( ), got {line[:60]!r}")
            name = hit[1]
        elif line == "END":
            ended = True
        elif hit := _SET.match(line):
            pose, key = (cell.tool, "machine.robot.tool") if hit[1] == "$TOOL" else (cell.ring, "machine.robot.positioner.origin")
            same_frame(pose, _frame(_aggregate(hit[2], _FRAME_KEYS, source, n, hit[1])), source, n, hit[1], key)
        elif hit := _SYSVAR.match(line):
            if hit[1] == "$VEL.CP":
                speed, mode = seconds(hit[3], source, n, "$VEL.CP (m/s)"), "cp"
                if speed > MAX_CP:
                    raise ConfigError(f"{source}: line {n}: $VEL.CP must be at most {MAX_CP:g} m/s, got {hit[3][:40]}")
            elif hit[1] == "$APO.CDIS":
                seconds(hit[3], source, n, "$APO.CDIS (mm)")
            else:
                value = seconds(hit[3], source, n, f"{hit[1]} (%)")
                if value > 100.0:
                    raise ConfigError(f"{source}: line {n}: {hit[1]} must be at most 100 %, got {hit[3][:40]}")
                if hit[2] == "1":
                    share = value
                    mode = "ext" if share < 100.0 else mode
        elif hit := _PTP.match(line):
            values = _aggregate(hit[1], _AXES_KEYS, source, n, "PTP")
            if start is None:
                if points_lin:
                    raise ConfigError(f"{source}: line {n}: the start PTP must come before the first LIN")
                start, start_line = np.array(values[:6]), n
            elif not points_lin or len(points_lin) - 1 in bridges:
                raise ConfigError(f"{source}: line {n}: a PTP within the program must follow a LIN (a bridge)")
            else:
                bridges[len(points_lin) - 1] = (np.array(values[:6]), n)
        elif hit := _LIN.match(line):
            if start is None:
                raise ConfigError(f"{source}: line {n}: a LIN before the start PTP")
            if rows.key == (0, 0, 0):
                raise ConfigError(f"{source}: line {n}: a move before any 'layer L circuit C pass P kind' comment")
            points_lin.append((hit[1], n, mode, speed, share, rows.key, rows.kind, rows.tension))
        else:
            raise ConfigError(f"{source}: line {n}: not a statement of winder's KRL programs, got {line[:60]!r}")
    if not ended:
        raise ConfigError(f"{source}: the .src stops without END: cut short?")
    points = _dat(all_lines[dat_at:], [name or ""] + modules, source)
    table = []
    # the rows are added once the .dat is read: each with the pass and the tension set where its LIN stands
    for k, (point, n, mode, speed, share, rows.key, rows.kind, rows.tension) in enumerate(points_lin):
        if point not in points:
            raise ConfigError(f"{source}: line {n}: {point} is not declared in the .dat")
        p = points[point]
        if k:
            q = table[-1]
            if mode == "cp":
                if np.isnan(speed):
                    raise ConfigError(f"{source}: line {n}: a LIN before any $VEL.CP")
                secs = float(np.linalg.norm(np.subtract(p[:3], q[:3]))) / (speed * 1000.0)
            else:
                secs = abs(p[8] - q[8]) / (share / 100.0 * top_e1)
        else:
            secs = 0.0
        rows.add(n, secs, point)
        table.append(p)
    arr = np.array(table, dtype=float).reshape(-1, 14)
    frames = frames_of(arr[:, :3], _frame_rotations(arr[:, 3:6]))
    return CellRead(rows, frames, arr[:, 8:11], start if start is not None else np.zeros(6), start_line, bridges)


def _frame_rotations(abc: np.ndarray) -> np.ndarray:
    from scipy.spatial.transform import Rotation  # noqa: PLC0415

    if abc.shape[0] == 0:
        return np.zeros((0, 3, 3))
    return Rotation.from_euler("ZYX", abc, degrees=True).as_matrix()
