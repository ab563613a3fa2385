"""Local registry of LeRobot policies by name and revision, usable offline.

Layout (root: $JOSHUA_MODEL_REGISTRY, default ~/.cache/joshua/models):

    <root>/<name>/<revision>/            the policy files, as saved by LeRobot or joshua-train
    <root>/<name>/<revision>/joshua_model.json   name, revision, type, import order, source, files, digest, lineage

A policy is a LeRobot policy directory, or a `joshua-train rl` output (policy.safetensors with
joshua_policy.json, type `sb3-ppo`). The lineage (what it was trained on, steps, seed, evaluation)
is copied from the joshua_policy.json that `joshua-train` writes next to every policy.

Models are data: import copies regular files only (a symbolic link or a special file is refused,
named) and refuses a copy holding a pickle or code in a processor pipeline (data_only.py). With
`trust_pickle`, the stable-baselines3 `policy.zip` of an earlier joshua-train is converted to
weights and JSON (which unpickles it: for one's own files only); `pull` never does that.

`files` maps every file of the entry but joshua_model.json to its SHA-256, and `digest` is the
SHA-256 of that list (`<sha256>  <path>` lines, sorted): it covers every byte an INFERENCE node
serves, and `verify` refuses an entry whose files changed, went missing or were added since.
`registry:NAME` resolves to the revision imported last, `registry:NAME@REVISION` to that one.
A revision defaults to the first 12 hex digits of the digest, so importing the same files twice is
a no-op. Entries appear atomically (copied aside, then renamed into place).
The Hugging Face Hub is used only by `pull`, never by resolution.
"""

import hashlib
import json
import os
import re
import shutil
import stat
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

from joshua_core.models import REGISTRY_DEFAULT_ROOT, REGISTRY_ENTRY_FILE, REGISTRY_ENV, REGISTRY_PREFIX
from joshua_runtime.ai import data_only, model_files, saved_policy
from joshua_runtime.errors import JoshuaError

DEFAULT_ROOT = REGISTRY_DEFAULT_ROOT
REF_PREFIX = REGISTRY_PREFIX
ENTRY_FILE = REGISTRY_ENTRY_FILE
DIGEST_LENGTH = 12
# Intermediate checkpoints of a training run are not part of the policy.
TRAINING_CHECKPOINTS = "checkpoints"
# What huggingface_hub keeps next to a download in a local directory: not part of the policy.
HUB_DOWNLOAD_METADATA = ".cache"
COPY_BLOCK_BYTES = 1 << 20
_NAME = re.compile(r"^[A-Za-z0-9][A-Za-z0-9._-]{0,127}$")


class RegistryError(JoshuaError):
    """A registry entry is missing, malformed or in conflict."""


@dataclass(frozen=True)
class Entry:
    name: str
    revision: str
    path: Path
    policy_type: str
    sequence: int
    imported_at: str
    source: str
    digest: str
    lineage: dict | None = None
    files: dict[str, str] | None = None  # relative path -> SHA-256; None for entries of earlier versions

    def lineage_text(self) -> str:
        """`so100_reach, 30000 steps, seed 0, success 0.43` (or `-` when unknown)."""
        if not self.lineage:
            return "-"
        parts = [str(self.lineage.get("env") or self.lineage.get("dataset") or "?")]
        if self.lineage.get("steps") is not None:
            parts.append(f"{self.lineage['steps']} steps")
        if self.lineage.get("seed") is not None:
            parts.append(f"seed {self.lineage['seed']}")
        evaluation = self.lineage.get("evaluation")
        if isinstance(evaluation, dict):
            parts.append(
                f"success {evaluation.get('success_rate')} over {evaluation.get('episodes')} episodes "
                f"(return {evaluation.get('mean_return')})"
            )
        return ", ".join(parts)


def root() -> Path:
    return Path(os.environ.get(REGISTRY_ENV) or DEFAULT_ROOT).expanduser()


def is_reference(model_path: str) -> bool:
    return model_path.startswith(REF_PREFIX)


def parse_reference(reference: str) -> tuple[str, str | None]:
    """`registry:NAME@REV` -> (NAME, REV); `registry:NAME` -> (NAME, None)."""
    body = reference[len(REF_PREFIX) :] if is_reference(reference) else reference
    name, _, revision = body.partition("@")
    check_name(name, "model name")
    if revision:
        check_name(revision, "revision")
    return name, revision or None


def check_name(text: str, what: str) -> None:
    if not _NAME.match(text or ""):
        raise RegistryError(f"invalid {what} {text!r}: use letters, digits, '.', '_' or '-'")


def entries(name: str | None = None) -> list[Entry]:
    """Every entry (of one name), oldest import first."""
    base = root()
    if name:
        names = [name]
    elif base.is_dir():
        names = sorted(p.name for p in base.iterdir() if p.is_dir())
    else:
        names = []
    found = []
    for model in names:
        directory = base / model
        if not directory.is_dir():
            continue
        for revision_dir in directory.iterdir():
            entry = _read_entry(revision_dir)
            if entry is not None:
                found.append(entry)
    return sorted(found, key=lambda e: (e.name, e.sequence, e.imported_at))


def resolve(reference: str) -> Entry:
    """The entry named by `registry:NAME[@REV]` (the latest import when no revision is given)."""
    name, revision = parse_reference(reference)
    if revision is not None:
        entry = _read_entry(root() / name / revision)
        if entry is None:
            raise RegistryError(f"{REF_PREFIX}{name}@{revision} is not in the registry at {root()}")
        return entry
    found = entries(name)
    if not found:
        raise RegistryError(f"{REF_PREFIX}{name} is not in the registry at {root()}")
    return found[-1]


def import_policy(
    path: str | Path, name: str, revision: str | None = None, source: str | None = None, trust_pickle: bool = False
) -> Entry:
    """Copy the policy at `path` into the registry as NAME@REVISION; return the entry."""
    check_name(name, "model name")
    if revision is not None:
        check_name(revision, "revision")
    policy_dir, policy_type = policy_files(path)
    metadata = saved_policy.read(policy_dir)
    (root() / name).mkdir(parents=True, exist_ok=True)
    staging = Path(tempfile.mkdtemp(prefix=".import-", dir=root() / name))
    try:
        copy = staging / "policy"
        _copy_regular_files(policy_dir.resolve(), copy, policy_dir, top=True)
        if trust_pickle and policy_type == saved_policy.KIND_PPO and not (copy / saved_policy.PPO_FILE).exists():
            from joshua_runtime.ai import ppo_files

            ppo_files.convert_pickled(copy)
            metadata = saved_policy.read(copy)
        names = model_files.feature_names(policy_dir)
        if names:
            model_files.write_feature_names(copy, names)
        data_only.check(copy, shown_as=policy_dir)
        files = file_digests(copy)
        digest = files_digest(files)
        revision = revision or digest[:DIGEST_LENGTH]
        target = root() / name / revision
        existing = _read_entry(target)
        if existing is not None:
            if existing.digest == digest:
                return existing
            raise RegistryError(f"{name}@{revision} already exists with different files")
        record = {
            "name": name,
            "revision": revision,
            "policy_type": policy_type,
            "sequence": 1 + max((e.sequence for e in entries(name)), default=0),
            "imported_at": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime()),
            "source": source or str(Path(path).resolve()),
            "files": files,
            "digest": digest,
            "lineage": {k: v for k, v in metadata.items() if k != "kind"} if metadata else None,
        }
        (copy / ENTRY_FILE).write_text(json.dumps(record, indent=2) + "\n")
        try:
            os.rename(copy, target)
        except OSError as exc:
            raise RegistryError(f"cannot add {name}@{revision}: {exc}") from exc
    finally:
        shutil.rmtree(staging, ignore_errors=True)
    entry = _read_entry(target)
    assert entry is not None
    return entry


def verify(entry: Entry) -> None:
    """Refuse an entry whose files are not exactly, byte for byte, those it was imported with."""
    reference = f"{REF_PREFIX}{entry.name}@{entry.revision}"
    if entry.files is None:
        raise RegistryError(
            f"{reference} was imported without a list of its files (by an earlier version); import the policy again"
        )
    present = file_digests(entry.path)
    again = "import the policy again"
    for name in sorted(set(entry.files) | set(present)):
        if name not in present:
            raise RegistryError(f"{reference}: {name} is missing since import; {again}")
        if name not in entry.files:
            raise RegistryError(f"{reference}: {name} was added after import; {again}")
        if present[name] != entry.files[name]:
            raise RegistryError(
                f"{reference}: {name} changed after import "
                f"(its SHA-256 is not the one in {entry.path / ENTRY_FILE}); {again}"
            )
    if files_digest(entry.files) != entry.digest:
        raise RegistryError(
            f"{reference}: the file list in {entry.path / ENTRY_FILE} does not match its digest; {again}"
        )


def file_digests(directory: Path) -> dict[str, str]:
    """{relative path: SHA-256} of every file of an entry (or a staged copy) but joshua_model.json."""
    digests = {}
    for path in _regular_files(directory):
        relative = path.relative_to(directory).as_posix()
        if relative == ENTRY_FILE:
            continue
        sha = hashlib.sha256()
        with open(path, "rb") as stream:
            for block in iter(lambda: stream.read(COPY_BLOCK_BYTES), b""):
                sha.update(block)
        digests[relative] = sha.hexdigest()
    return digests


def files_digest(files: dict[str, str]) -> str:
    """The SHA-256 of the file list as `sha256sum` prints it (`<sha256>  <path>` lines, sorted by path)."""
    return hashlib.sha256("".join(f"{files[p]}  {p}\n" for p in sorted(files)).encode()).hexdigest()


def policy_files(path: str | Path) -> tuple[Path, str]:
    """(directory, type) of the policy at `path`: a `joshua-train rl` output or a LeRobot policy."""
    base = Path(path).expanduser()
    if base.is_dir() and saved_policy.is_ppo(base):
        if not any((base / f).is_file() for f in (saved_policy.PPO_FILE, saved_policy.LEGACY_PPO_FILE)):
            raise RegistryError(f"{base} holds no {saved_policy.PPO_FILE} yet (training has not finished)")
        return base, saved_policy.KIND_PPO
    policy_dir = model_files.policy_directory(path)
    return policy_dir, model_files.policy_type(policy_dir)


def pull(repo_id: str, name: str | None = None, hub_revision: str | None = None) -> Entry:
    """Download a policy from the Hugging Face Hub and import it (the only networked operation)."""
    from huggingface_hub import snapshot_download
    from huggingface_hub.errors import HfHubHTTPError, LocalEntryNotFoundError

    name = name or repo_id.rsplit("/", 1)[-1]
    check_name(name, "model name")
    with tempfile.TemporaryDirectory(prefix="joshua-pull-") as download:
        try:
            snapshot_download(repo_id=repo_id, revision=hub_revision, local_dir=download)
        except (HfHubHTTPError, LocalEntryNotFoundError, OSError, ValueError) as exc:
            first_line = str(exc).strip().splitlines()[0] if str(exc).strip() else type(exc).__name__
            raise RegistryError(f"cannot download {repo_id} from the Hugging Face Hub: {first_line}") from exc
        shutil.rmtree(Path(download) / HUB_DOWNLOAD_METADATA, ignore_errors=True)
        source = f"hf://{repo_id}" + (f"@{hub_revision}" if hub_revision else "")
        return import_policy(download, name, source=source)  # never trusts a pickle


def remove(reference: str) -> Entry:
    """Delete one revision (`registry:NAME@REV` or NAME@REV)."""
    name, revision = parse_reference(reference)
    if revision is None:
        raise RegistryError("give the revision to remove: NAME@REVISION")
    entry = resolve(f"{REF_PREFIX}{name}@{revision}")
    shutil.rmtree(entry.path)
    if not any((root() / name).iterdir()):
        (root() / name).rmdir()
    return entry


def _copy_regular_files(source: Path, target: Path, shown: Path, top: bool = False) -> None:
    """Copy the directories and regular files below `source` (modes kept); refuse links and special files.

    At the top, the registry's own file and training checkpoints are left out. Files are opened
    without following links, so a file swapped for a link while copying is refused too."""
    target.mkdir()
    for item in sorted(os.scandir(source), key=lambda e: e.name):
        if top and item.name in (ENTRY_FILE, TRAINING_CHECKPOINTS):
            continue
        if item.is_symlink():
            raise RegistryError(
                f"{shown / item.name} is a symbolic link: a policy is imported from regular files only "
                "(copy the file in its place)"
            )
        if item.is_dir(follow_symlinks=False):
            _copy_regular_files(Path(item.path), target / item.name, shown / item.name)
            continue
        try:
            descriptor = os.open(item.path, os.O_RDONLY | os.O_NOFOLLOW)
        except OSError as exc:
            raise RegistryError(f"cannot read {shown / item.name}: {exc.strerror}") from exc
        with open(descriptor, "rb") as stream:
            mode = os.fstat(descriptor).st_mode
            if not stat.S_ISREG(mode):
                raise RegistryError(f"{shown / item.name} is not a regular file")
            with open(target / item.name, "xb") as copy:
                shutil.copyfileobj(stream, copy, COPY_BLOCK_BYTES)
                os.fchmod(copy.fileno(), stat.S_IMODE(mode))


def _regular_files(directory: Path):
    """Every file below a registry entry, sorted; a link or special file there is refused."""
    for item in sorted(os.scandir(directory), key=lambda e: e.name):
        path = Path(item.path)
        if item.is_symlink():
            raise RegistryError(
                f"{path} is a symbolic link, which a registry entry never holds; import the policy again"
            )
        if item.is_dir(follow_symlinks=False):
            yield from _regular_files(path)
        elif item.is_file(follow_symlinks=False):
            yield path
        else:
            raise RegistryError(f"{path} is not a regular file, which a registry entry never holds")


def _read_entry(directory: Path) -> Entry | None:
    try:
        record = json.loads((directory / ENTRY_FILE).read_text())
        return Entry(
            name=record["name"],
            revision=record["revision"],
            path=directory,
            policy_type=record["policy_type"],
            sequence=int(record["sequence"]),
            imported_at=record["imported_at"],
            source=record.get("source", ""),
            digest=record["digest"],
            lineage=record.get("lineage"),
            files=record.get("files"),
        )
    except (OSError, ValueError, KeyError, TypeError):
        return None
