"""Regression samples: recompute each sample job and compare it with its stored reference outputs.

Layout of a sample folder DIR:

    DIR/<sample>.yaml                 a job file
    DIR/reference/<sample>/           the outputs of `winder run DIR/<sample>.yaml`:
        <name>.csv, <name>.gcode, <name>.summary.json   (and <name>.ply, <name>.layup.csv, only if stored)

Comparison within tolerances (a unit in the last printed place): winder.app.compare.

No click here: winder.cli prints what this module returns.
"""

from __future__ import annotations

import shutil
import tempfile
from collections.abc import Callable, Sequence
import dataclasses
from pathlib import Path

from winder.errors import ConfigError
from winder.export import registry
from winder.app.compare import (JSON_ATOL, JSON_RTOL, PRINT_SLACK, REL_NOISE, Difference, compare_bytes,
                                compare_csv, compare_lines)
from winder.app.compare_files import compare_file
from winder.app.compare_summary import compare_json
from winder.app.jobs import JobReport, JobTask, exit_status, run_job, run_jobs

__all__ = [
    "Difference", "FileCheck", "JSON_ATOL", "JSON_RTOL", "PRINT_SLACK", "REL_NOISE", "SampleResult", "Sample",
    "compare_bytes", "compare_csv", "compare_file", "compare_json", "compare_lines", "find_samples",
    "format_result", "regress",
]

REFERENCE = "reference"
# The outputs stored as references; a PLY only where the reference folder already holds one.
REFERENCE_FORMATS = ("csv", "gcode")
# A reference file past this is not read (the largest job the work budget allows writes about 150 MB
# per file): a difference, not unbounded memory.
MAX_REFERENCE_BYTES = 400_000_000
# Nor is one much larger than the output it is compared with (decided from the sizes, before reading):
# a difference in size this large is no rounding, and memory stays a few times the output's.
REFERENCE_SIZE_FACTOR = 4
REFERENCE_SIZE_SLACK = 1_000_000


# -- what is compared ------------------------------------------------------------------------------
@dataclasses.dataclass(frozen=True)
class Sample:
    """A sample job and the folder of its reference outputs."""

    name: str
    config: Path
    reference: Path


@dataclasses.dataclass(frozen=True)
class FileCheck:
    """The comparison of one output file. status: same | differs | missing (not produced) |
    unexpected (produced, no reference) | orphaned (a reference, no sample) | new / changed / refreshed /
    removed (with --update)."""

    file: str
    status: str
    differences: tuple[Difference, ...] = ()
    count: int = 0  # all differences; only the first MAX_SHOWN are kept

    @property
    def ok(self) -> bool:
        return self.status in ("same", "new", "changed", "refreshed", "removed")


@dataclasses.dataclass(frozen=True)
class SampleResult:
    sample: Sample
    report: JobReport
    files: tuple[FileCheck, ...] = ()
    updated: bool = False

    @property
    def ok(self) -> bool:
        return self.report.ok and all(f.ok for f in self.files)

    @property
    def exit_code(self) -> int:
        if not self.report.ok:
            return self.report.exit_code
        return 0 if self.ok else 1


# -- samples ---------------------------------------------------------------------------------------
def find_samples(directory: str | Path) -> list[Sample]:
    """The samples of DIR (its *.yaml / *.yml files), sorted by name."""
    from winder.export.paths import check_path  # noqa: PLC0415

    check_path(directory, "DIRECTORY")
    root = Path(directory)
    if not root.exists():
        raise ConfigError(f"{directory}: no such folder")
    if not root.is_dir():
        raise ConfigError(f"{directory}: not a folder of samples")
    named = sorted(p for p in root.iterdir() if p.suffix in (".yaml", ".yml"))
    broken = [p for p in named if not p.exists()]
    if broken:  # a sample that silently stopped being checked would pass CI forever
        raise ConfigError(f"{broken[0]}: a sample that is a broken link")
    configs = [p for p in named if p.is_file()]
    if not configs:
        raise ConfigError(f"{directory}: no samples (*.yaml) in this folder")
    return [Sample(p.stem, p, root / REFERENCE / p.stem) for p in configs]


def find_orphans(directory: str | Path, samples: Sequence[Sample]) -> list[Sample]:
    """The reference folders of DIR with no sample beside them (its sample deleted or renamed), as
    samples whose config is missing: a CI that silently stopped checking one would pass forever."""
    root = Path(directory) / REFERENCE
    if not root.is_dir():
        return []
    names = {s.name for s in samples}
    return [Sample(p.name, Path(directory) / f"{p.name}.yaml", p) for p in sorted(root.iterdir())
            if p.is_dir() and not p.name.startswith(".") and p.name not in names]


def _orphan(sample: Sample, update: bool) -> SampleResult:
    """The result of a reference without its sample: a failure, or with update its outputs removed."""
    report = JobReport(str(sample.config), sample.name, True, 0, "")
    if not update:
        return SampleResult(sample, report, (FileCheck(str(sample.reference), "orphaned", (Difference(
            "sample", f"{sample.config.name} (this folder is its reference)", "no such file",
            "restore the sample, or remove its reference with `winder regress --update`"),), 1),))
    checks = []
    for file_name in sorted(_reference_files(sample)):
        if file_name.endswith(registry.suffixes()):
            (sample.reference / file_name).unlink()
            checks.append(FileCheck(file_name, "removed"))
    if not any(sample.reference.iterdir()):
        sample.reference.rmdir()
    return SampleResult(sample, report, tuple(checks), updated=True)


def _reference_files(sample: Sample) -> dict[str, int]:
    """The reference's files: name -> size (read one by one, when compared: _read_reference)."""
    if not sample.reference.is_dir():
        return {}
    return {p.name: p.stat().st_size for p in sorted(sample.reference.iterdir())
            if p.is_file() and not p.name.startswith(".")}


def _reference_limit(got: bytes) -> int:
    return min(MAX_REFERENCE_BYTES, REFERENCE_SIZE_FACTOR * len(got) + REFERENCE_SIZE_SLACK)


def _read_reference(sample: Sample, file_name: str, size: int, got: bytes) -> bytes | None:
    """The reference file's bytes, or None when it is past _reference_limit (not read)."""
    if size > _reference_limit(got):
        return None
    with open(sample.reference / file_name, "rb") as fh:
        return fh.read(_reference_limit(got) + 1)  # a file that grew since: still bounded


def _too_large(file_name: str, size: int, got: bytes) -> FileCheck:
    return FileCheck(file_name, "differs", (Difference(
        "file size", f"at most {_reference_limit(got):,} bytes (regress reads a reference of up to "
        f"{REFERENCE_SIZE_FACTOR}x its output's {len(got):,} bytes plus {REFERENCE_SIZE_SLACK:,}, and never past "
        f"{MAX_REFERENCE_BYTES:,})", f"{size:,} bytes", "not read"),), 1)


def _formats_for(sample: Sample) -> tuple[str, ...]:
    formats = list(REFERENCE_FORMATS)
    for extra in ("ply", "layup"):  # compared where the reference holds one
        if sample.reference.is_dir() and any(sample.reference.glob("*" + registry.suffix_of(extra))):
            formats.append(extra)
    return tuple(formats)


def _check(sample: Sample, report: JobReport) -> tuple[FileCheck, ...]:
    reference = _reference_files(sample)
    got = {Path(p).name: Path(p).read_bytes() for p in report.outputs}
    checks = []
    if not reference:
        return (FileCheck(str(sample.reference), "missing",
                          (Difference("reference", "stored outputs", "none",
                                      "create them with `winder regress --update`"),), 1),)
    for file_name in sorted(set(reference) | set(got)):
        if file_name not in got:
            checks.append(FileCheck(file_name, "missing", (Difference(
                "file", "present (in the reference)", "not produced"),), 1))
        elif file_name not in reference:
            checks.append(FileCheck(file_name, "unexpected", (Difference(
                "file", "absent (not in the reference)", "produced"),), 1))
        elif (expected := _read_reference(sample, file_name, reference[file_name], got[file_name])) is None:
            checks.append(_too_large(file_name, reference[file_name], got[file_name]))
        else:
            shown, count = compare_file(file_name, expected, got[file_name])
            checks.append(FileCheck(file_name, "differs" if count else "same", tuple(shown), count))
    return tuple(checks)


def _update(sample: Sample, report: JobReport) -> tuple[FileCheck, ...]:
    """Rewrite the sample's reference folder with the new outputs, as one set (winder.app.writes: a
    reference folder never holds files of two runs); say what changed."""
    from winder.app.writes import write_outputs  # noqa: PLC0415

    reference = _reference_files(sample)
    got = {Path(p).name: Path(p).read_bytes() for p in report.outputs}
    checks, rewrite = [], {}
    for file_name, data in got.items():
        expected = _read_reference(sample, file_name, reference[file_name], data) if file_name in reference else None
        if expected is None:  # absent, or too large to read
            rewrite[file_name] = data
            checks.append(FileCheck(file_name, "new"))
            continue
        shown, count = compare_file(file_name, expected, data)
        if expected != data:
            rewrite[file_name] = data
        status = "changed" if count else ("refreshed" if expected != data else "same")
        checks.append(FileCheck(file_name, status, tuple(shown), count))
    if rewrite:
        write_outputs(sample.reference, rewrite)
    for file_name in reference:
        if file_name not in got and file_name.endswith(registry.suffixes()):
            (sample.reference / file_name).unlink()
            checks.append(FileCheck(file_name, "removed"))
    return tuple(checks)


def regress(directory: str | Path, update: bool = False, workers: int = 1,
            on_result: Callable[[SampleResult], None] | None = None,
            job: Callable[..., JobReport] = run_job) -> list[SampleResult]:
    """Recompute every sample of directory (in temporary folders) and compare with, or with update
    rewrite, its reference. on_result is called as each sample finishes; the list returned is in
    sample order. Raises ConfigError if directory holds no samples."""
    samples = find_samples(directory)
    orphans = find_orphans(directory, samples)
    results: list[SampleResult | None] = [None] * len(samples)
    with tempfile.TemporaryDirectory(prefix="winder-regress-") as tmp:
        tasks = []
        for i, sample in enumerate(samples):
            out = Path(tmp) / f"{i:03d}-{sample.name}"
            out.mkdir()
            # The bare file name as the source: outputs may record it, and must not depend on the
            # folder the samples are run from.
            tasks.append(JobTask(str(sample.config), str(out), _formats_for(sample), sample.config.name))
        for i, report in run_jobs(tasks, workers, job=job):
            sample = samples[i]
            if not report.ok:
                result = SampleResult(sample, report)
            elif update:
                result = SampleResult(sample, report, _update(sample, report), updated=True)
            else:
                result = SampleResult(sample, report, _check(sample, report))
            shutil.rmtree(tasks[i].out_dir, ignore_errors=True)
            results[i] = result
            if on_result is not None:
                on_result(result)
    return [r for r in results if r is not None] + [_orphan(o, update) for o in orphans]


def regress_exit_status(results: Sequence[SampleResult]) -> int:
    return exit_status(r.exit_code for r in results)


def _full_path(result: SampleResult) -> str:
    """The job's message, naming the sample by its path rather than the bare file name."""
    message, bare = result.report.message, result.sample.config.name
    return str(result.sample.config) + message[len(bare):] if message.startswith(f"{bare}:") else message


def format_result(result: SampleResult) -> list[str]:
    """Readable lines about one sample: a status line, then (on failure) file and differences."""
    s, r = result.sample, result.report
    if not r.ok:
        return [f"FAIL {s.name}: the job failed: {_full_path(result)}"]
    if any(f.status == "orphaned" for f in result.files):
        return [f"FAIL {s.name}: {s.reference} holds the reference of {s.config.name}, which is not there "
                "(restore the sample, or remove its reference with `winder regress --update`)"]
    if result.updated and not s.config.exists():
        return [f"removed {s.name}: the reference of a sample that is not there ({s.reference})"]
    if result.updated:
        changed = [f for f in result.files if f.status != "same"]
        if not changed:
            return [f"same {s.name}: references unchanged ({len(result.files)} files, {r.seconds:.1f} s)"]
        lines = [f"updated {s.name} ({r.seconds:.1f} s):"]
        for f in result.files:
            if f.status == "changed":
                lines.append(f"  {f.file}: changed, {f.count} difference{'s' if f.count != 1 else ''}"
                             + (":" if f.differences else ""))
                lines.extend(f"    {d.where}: was {d.expected}, now {d.got}" + (f" ({d.note})" if d.note else "")
                             for d in f.differences)
                if f.count > len(f.differences):
                    lines.append(f"    ... and {f.count - len(f.differences)} more")
            elif f.status == "refreshed":
                lines.append(f"  {f.file}: rewritten (differences within tolerance only)")
            elif f.status != "same":
                lines.append(f"  {f.file}: {f.status}")
        return lines
    if result.ok:
        return [f"ok   {s.name} ({len(result.files)} files, {r.seconds:.1f} s)"]
    lines = [f"FAIL {s.name} ({s.config}): differs from {s.reference}"]
    for f in result.files:
        if f.ok:
            continue
        lines.append(f"  {f.file}: {f.status}, {f.count} difference{'s' if f.count != 1 else ''}"
                     + (f" (first {len(f.differences)} shown)" if f.count > len(f.differences) else "") + ":")
        lines.extend(f"    {d}" for d in f.differences)
    return lines


def failure_line(result: SampleResult) -> str:
    """The one `Error:` line (without the prefix) of a failing sample."""
    if not result.report.ok:
        return _full_path(result)
    bad = [f for f in result.files if not f.ok]
    if any(f.status == "orphaned" for f in bad):
        return f"{result.sample.config}: no such sample, but {result.sample.reference} holds its reference"
    total = sum(f.count for f in bad)
    return (f"{result.sample.config}: {total} difference{'s' if total != 1 else ''} from the reference "
            f"in {', '.join(f.file for f in bad)}")


def tally_line(results: Sequence[SampleResult], update: bool) -> str:
    """The last line of `regress`: how many samples passed (or were updated) and failed."""
    n, bad = len(results), sum(not r.ok for r in results)
    failed = f", {bad} failed" if bad else ""
    if update:
        changed = sum(any(f.status != "same" for f in r.files) for r in results if r.ok)
        return f"{n} sample{'s' if n != 1 else ''}: {changed} updated, {n - changed - bad} unchanged{failed}"
    return f"{n} sample{'s' if n != 1 else ''}: {n - bad} passed{failed}"
