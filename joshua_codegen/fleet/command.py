"""`joshuac build FLEET -o OUT`: check the fleet, build one release per robot and the Ansible files, write OUT."""

import sys
from pathlib import Path

import click

from joshua_codegen.cli import EXIT_ERRORS, EXIT_OK, report


def build_fleet(config: str, out: Path, overrides, output_format: str, signer, check_only: bool) -> int:
    from joshua_codegen.bundle import BundleError
    from joshua_codegen.check import check_file
    from joshua_codegen.fleet.releases import fleet_files, plan_fleet
    from joshua_codegen.write import OutputError, diff_tree, write_tree

    result = check_file(config, overrides)
    report([result], output_format, sys.stderr if output_format == "text" else sys.stdout)
    if result.has_errors:
        return EXIT_ERRORS
    try:
        fleet = plan_fleet(result, signer)
    except BundleError as exc:
        click.echo(f"joshuac: error: {exc}", err=True)
        return EXIT_ERRORS
    files = fleet_files(fleet)
    if check_only:
        difference = diff_tree(files, out)
        if difference:
            click.echo(difference.text, nl=False)
            click.echo(f"joshuac: {out} is not up to date with {config} ({difference.summary()})", err=True)
            return EXIT_ERRORS
        return EXIT_OK
    try:
        write_tree(files, out)
    except OutputError as exc:
        click.echo(f"joshuac: error: {exc}", err=True)
        return EXIT_ERRORS
    signed = " signed" if signer else ""
    for release in fleet.releases:
        click.echo(f"joshuac: {release.name}: release {release.release}{signed} in {out}/{release.directory}", err=True)
    click.echo(f"joshuac: wrote {len(files)} files to {out}", err=True)
    return EXIT_OK
