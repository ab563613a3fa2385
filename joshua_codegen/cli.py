"""`joshuac`: the command line. Thin: every command calls check, plan, render and write."""

import posixpath
import sys
import tempfile
from pathlib import Path

import click

from joshua_codegen.version import VERSION

FORMATS = ("text", "json", "github", "sarif")
EXIT_OK, EXIT_ERRORS, EXIT_USAGE, EXIT_INTERNAL = 0, 1, 2, 70
# Room under --prefix for the longest path joshuac writes there (systemd/joshua-<64>-<128>.service).
PREFIX_ROOM = "x" * 255

set_option = click.option(
    "--set",
    "overrides",
    multiple=True,
    metavar="KEY=VALUE",
    help="Override a field before validation, e.g. mode=MODE_SIMULATION or NODE.qos_depth=10 (repeatable). "
    "Lists replace the whole list: NODE.device_ids=1,2,3 or NODE.device_ids=[1,2,3].",
)
format_option = click.option(
    "--format",
    "output_format",
    type=click.Choice(FORMATS),
    default="text",
    show_default=True,
    help="How diagnostics are printed.",
)
config_argument = click.argument("config", type=click.Path(exists=True, dir_okay=False))


def _absolute_prefix(_ctx, _param, value):
    """--prefix must be an absolute, printable, normalized path: units and configs refer to files under it."""
    if value is None:
        return None
    from joshua_codegen.rules.e119_path_too_long import path_problem

    if not value.startswith("/"):
        raise click.BadParameter(f"{value!r} is not an absolute path")
    if not value.isprintable():
        raise click.BadParameter(f"{value!r} contains control characters")
    normal = posixpath.normpath(value).replace("//", "/", 1)
    if value != normal:
        raise click.BadParameter(
            f"{value!r} is not a normalized path (no '.', '..', '//' or trailing '/'); write {normal!r}"
        )
    if "=" in value:
        raise click.BadParameter(f"{value!r} contains '=', which env(1) would read as a variable assignment")
    problem = path_problem(posixpath.join(value, PREFIX_ROOM))
    if problem is not None:
        raise click.BadParameter(f"{value!r} is too long: with the files under it, it {problem}")
    return value


def report(results, output_format: str, stream) -> None:
    """Print the diagnostics of one or more check results."""
    from joshua_codegen.diagnostics import format_github, format_json, sort_diagnostics

    diagnostics = sort_diagnostics([d for r in results for d in r.diagnostics])
    if output_format == "json":
        click.echo(format_json(diagnostics), file=stream, nl=False)
    elif output_format == "github":
        click.echo(format_github(diagnostics), file=stream, nl=False)
    elif output_format == "sarif":
        from joshua_codegen.sarif import format_sarif

        click.echo(format_sarif(diagnostics), file=stream, nl=False)
    elif diagnostics:
        report_texts(diagnostics, {path: text for r in results for path, text in r.sources.items()}, stream)


def report_texts(diagnostics, sources: dict[str, str], stream) -> None:
    """Print diagnostics as text, each with its source line."""
    from joshua_codegen.diagnostics import format_text

    click.echo(format_text(diagnostics, sources), file=stream, nl=False)


def compile_or_exit(config: str, overrides, output_format: str, prefix: str | None = None):
    from joshua_codegen.compile import compile_file

    compilation = compile_file(config, overrides, prefix)
    report([compilation.check], output_format, sys.stderr if output_format == "text" else sys.stdout)
    if compilation.files is None:
        sys.exit(EXIT_ERRORS)
    return compilation


@click.group(context_settings={"help_option_names": ["-h", "--help"]})
@click.version_option(VERSION, prog_name="joshuac")
def cli() -> None:
    """Check robot descriptions (.pbtxt) and generate what runs them."""


@cli.command()
@click.argument("configs", nargs=-1, required=True, type=click.Path(exists=True, dir_okay=False))
@set_option
@format_option
def check(configs, overrides, output_format) -> None:
    """Validate descriptions; print every problem with its position."""
    from joshua_codegen.check import check_file

    results = [check_file(path, overrides) for path in configs]
    report(results, output_format, sys.stdout)
    sys.exit(EXIT_ERRORS if any(r.has_errors for r in results) else EXIT_OK)


@cli.command()
@config_argument
@click.option("-o", "--out", "out", required=True, type=click.Path(file_okay=False), help="Output directory.")
@click.option(
    "--prefix",
    default=None,
    callback=_absolute_prefix,
    help="Absolute path where OUT lives on the robot. Default /opt/joshua/<robot>.",
)
@click.option("--check", "check_only", is_flag=True, help="Write nothing; exit 1 with a diff when OUT differs.")
@click.option(
    "--bundle",
    is_flag=True,
    help="Also write what a robot needs to run OUT without this repository: OUT/wheels/ and OUT/install.sh.",
)
@click.option(
    "--image",
    is_flag=True,
    help="Also write a container image's build context: the bundle, OUT/Containerfile and OUT/.containerignore.",
)
@click.option(
    "--sign",
    "sign_key",
    default=None,
    metavar="KEY",
    type=click.Path(dir_okay=False),
    help="Sign the stamp with this Ed25519 private key (joshuac keygen): OUT/.joshuac-stamp.sig.",
)
@set_option
@format_option
def build(config, out, prefix, check_only, bundle, image, sign_key, overrides, output_format) -> None:
    """Generate entrypoints, units, manifest and supervisor into OUT (a fleet file: one release per robot)."""
    from joshua_codegen.write import OutputError, diff_tree, write_tree

    signer = _signer(sign_key)
    if _is_fleet_file(config):
        from joshua_codegen.fleet.command import build_fleet

        if prefix is not None:
            raise click.UsageError(
                "a fleet's releases live in /opt/joshua/current on each robot: --prefix does not apply"
            )
        if image:
            raise click.UsageError(
                "a fleet's releases are rolled out over SSH, each with its bundle: --image does not apply"
            )
        sys.exit(build_fleet(config, Path(out), overrides, output_format, signer, check_only))
    compilation = compile_or_exit(config, overrides, output_format, prefix)
    if image:
        from joshua_codegen.image import ImageError, image_files
        from joshua_codegen.render import effective_prefix

        try:
            compilation.files = image_files(
                compilation.robot, effective_prefix(compilation.robot.name, prefix), compilation.files
            )
        except ImageError as exc:
            click.echo(f"joshuac: error: {exc}", err=True)
            sys.exit(EXIT_ERRORS)
    elif bundle:
        from joshua_codegen.bundle import BundleError, bundle_files

        try:
            compilation.files = {**compilation.files, **bundle_files(compilation.robot)}
        except BundleError as exc:
            click.echo(f"joshuac: error: {exc}", err=True)
            sys.exit(EXIT_ERRORS)
    if check_only:
        difference = diff_tree(compilation.files, Path(out))
        if difference:
            click.echo(difference.text, nl=False)
            click.echo(
                f"joshuac: {out} is not up to date with {config} ({difference.summary()}); "
                f"run: joshuac build {config} -o {out}",
                err=True,
            )
            sys.exit(EXIT_ERRORS)
        return
    try:
        write_tree(compilation.files, Path(out), signer)
    except OutputError as exc:
        click.echo(f"joshuac: error: {exc}", err=True)
        sys.exit(EXIT_ERRORS)
    click.echo(f"joshuac: wrote {len(compilation.files)} files to {out}" + (" (signed)" if signer else ""), err=True)


def _signer(key: str | None):
    """The signing function of `--sign KEY`, or None; a key that cannot be used ends joshuac with exit 1."""
    if key is None:
        return None
    from joshua_codegen.signing import SigningError, load_signer

    try:
        return load_signer(Path(key))
    except SigningError as exc:
        click.echo(f"joshuac: error: {exc}", err=True)
        sys.exit(EXIT_ERRORS)


def _is_fleet_file(config: str) -> bool:
    """Whether `config` is a fleet file (its first field is fleet_config); unreadable files are left to check."""
    from joshua_codegen.fleet.load import is_fleet_text
    from joshua_codegen.source_file import SourceProblem, read_description

    try:
        return is_fleet_text(read_description(config).decode("utf-8", errors="replace"))
    except SourceProblem:
        return False


@cli.command()
@click.argument("key", type=click.Path(dir_okay=False))
def keygen(key) -> None:
    """Make an Ed25519 key pair for signed releases: KEY (private, mode 0600) and KEY.pub (public)."""
    from joshua_codegen.signing import SigningError, generate_key_pair

    try:
        public = generate_key_pair(Path(key))
    except SigningError as exc:
        click.echo(f"joshuac: error: {exc}", err=True)
        sys.exit(EXIT_ERRORS)
    click.echo(f"joshuac: wrote {key} (private: keep it off the robots) and {public} (copy it to each robot)", err=True)


@cli.command()
@config_argument
@click.option("--format", "graph_format", type=click.Choice(("dot", "mermaid")), default="dot", show_default=True)
@set_option
def graph(config, graph_format, overrides) -> None:
    """Print the node/topic graph as Graphviz DOT or Mermaid."""
    compilation = compile_or_exit(config, overrides, "text")
    click.echo(compilation.files["topology.dot" if graph_format == "dot" else "topology.mmd"], nl=False)


@cli.command()
@click.argument("code", required=False)
def explain(code) -> None:
    """Explain a diagnostic code, e.g. joshuac explain E301; without one, list every code."""
    from joshua_codegen.rules import all_rules, summaries
    from joshua_codegen.rules import explain as explain_code

    if code is None:
        click.echo("".join(line + "\n" for line in summaries()), nl=False)
        return
    text = explain_code(code.upper())
    if text is None:
        known = ", ".join(sorted(rule.CODE for rule in all_rules()))
        click.echo(f"joshuac: unknown code {code!r}; known codes: {known}", err=True)
        sys.exit(EXIT_USAGE)
    click.echo(text)


@cli.command()
@click.argument("configs", nargs=-1, required=True, type=click.Path(exists=True, dir_okay=False))
@click.option("--check", "check_only", is_flag=True, help="Exit 1 when a file is not in canonical form.")
@click.option("-w", "--write", "write_back", is_flag=True, help="Rewrite the files in canonical form.")
def fmt(configs, check_only, write_back) -> None:
    """Print a description in canonical form (comments kept); --check or --write take several files.

    A file that is not valid UTF-8 text, or that cannot be parsed, is reported and never rewritten."""
    from joshua_codegen.fmt import format_file

    if len(configs) > 1 and not (check_only or write_back):
        raise click.UsageError("printing takes one file; use --check or --write for several")
    failed = False
    for config in configs:
        text, formatted, diagnostics = format_file(config)
        if formatted is None:
            report_texts(diagnostics, {config: text}, sys.stderr)
            failed = True
        elif check_only:
            if formatted != text:
                click.echo(f"joshuac: {config} is not formatted; run: joshuac fmt --write {config}", err=True)
                failed = True
        elif write_back:
            failed |= not _rewrite(config, text, formatted)
        else:
            click.echo(formatted, nl=False)
    sys.exit(EXIT_ERRORS if failed else EXIT_OK)


def _rewrite(config: str, text: str, formatted: str) -> bool:
    from joshua_codegen.write import OutputError, replace_file

    if formatted == text:
        return True
    try:
        replace_file(Path(config), formatted)
    except OutputError as exc:
        click.echo(f"joshuac: error: {exc}", err=True)
        return False
    return True


@cli.command()
def lsp() -> None:
    """Serve the Language Server Protocol on standard input and output, for editors."""
    from joshua_codegen.lsp.server import serve

    serve()


@cli.command(context_settings={"ignore_unknown_options": True})
@config_argument
@set_option
@click.option("--duration", type=float, default=None, help="Stop with the shutdown cascade after this many seconds.")
@click.option("--skip-preflight", is_flag=True, help="Start even when devices or models are missing.")
@click.option("--status-interval", type=float, default=None, help="Print one status line per node this often.")
@click.option("--host", "host", default=None, metavar="NAME", help="Run one host's part of a robot on several hosts.")
@click.option(
    "--watch",
    is_flag=True,
    help="Rebuild when the description or a file it names changes, and reload the running robot: only what "
    "changed restarts.",
)
def run(config, overrides, duration, skip_preflight, status_interval, host, watch) -> None:
    """Build into a temporary directory and run the supervisor in the foreground."""
    from joshua_codegen.run import HostChoiceError, host_directory, run_supervisor
    from joshua_codegen.write import write_tree

    with tempfile.TemporaryDirectory(prefix="joshuac-run-") as tmp:
        built = Path(tmp) / "out"
        compilation = compile_or_exit(config, overrides, "text", prefix=str(built))
        try:
            out = host_directory(compilation.robot, built, host)
        except HostChoiceError as exc:
            click.echo(f"joshuac: error: {exc}", err=True)
            sys.exit(EXIT_USAGE)
        write_tree(compilation.files, built)
        _print_dashboard_url(compilation, host)
        extra = []
        if duration is not None:
            extra += ["--duration", str(duration)]
        if skip_preflight:
            extra.append("--skip-preflight")
        if status_interval is not None:
            extra += ["--status-interval", str(status_interval)]
        follow = None
        if watch:
            from joshua_codegen.watch import Watcher

            locate = lambda robot, directory: host_directory(robot, directory, host)  # noqa: E731
            follow = Watcher(config, overrides, built, out, compilation.robot, locate).follow
        sys.exit(run_supervisor(out, extra, follow))


def _print_dashboard_url(compilation, host: str | None = None) -> None:
    """The dashboard's address with its token, on this command's own output: never in a node's log."""
    from joshua_codegen.run import dashboard_address
    from joshua_core.dashboard_token import TokenFileError

    config = compilation.check.description.robot_config
    try:
        address = dashboard_address(config, host)
    except TokenFileError as exc:
        click.echo(f"joshuac: error: {exc}", err=True)
        sys.exit(EXIT_ERRORS)
    if address:
        click.echo(f"joshuac: dashboard of {config.name}: {address}")


def main() -> None:
    """Console entry point: usage errors exit 2, unexpected failures a one-line internal error."""
    try:
        cli(standalone_mode=True)
    except SystemExit:
        raise
    except KeyboardInterrupt:
        sys.exit(130)
    except Exception as exc:  # a bug, but never a traceback for the user
        click.echo(f"joshuac: internal error: {type(exc).__name__}: {exc}", err=True)
        sys.exit(EXIT_INTERNAL)
