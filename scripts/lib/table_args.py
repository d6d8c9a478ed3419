"""The command line of the table scripts (scripts/ablation_table.py,
scripts/realism_targets.py): OUT NAME... (import with scripts/ on the path,
as it is for a script run from there)."""
import pathlib
import sys


def out_and_names(doc):
    """(OUT, [NAME, ...]) from sys.argv. -h or --help prints `doc` and exits
    0; fewer than two arguments exit 1 with `doc`."""
    if len(sys.argv) > 1 and sys.argv[1] in ("-h", "--help"):
        print(doc.strip())
        sys.exit(0)
    if len(sys.argv) < 3:
        sys.exit(doc)
    return pathlib.Path(sys.argv[1]), sys.argv[2:]
