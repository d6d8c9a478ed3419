# Option parsing and checks shared by the scripts in scripts/ and
# benchmarks/ (source scripts/lib/options.sh from the repository root).

# Prints the calling script's header comment (from line 2 to the first line
# that is not a comment) without the leading '# '.
script_help() {
  awk 'NR > 1 && /^#/ { sub(/^# ?/, ""); print; next } NR > 1 { exit }' "$0"
}

# For scripts with positional arguments: where the first is -h or --help,
# prints the header comment and exits 0.
help_if_asked() {
  case "${1:-}" in
    -h|--help) script_help; exit 0 ;;
  esac
}

# parse_options "NAME ..." "SWITCH ..." ARGUMENTS...
# Each "--NAME VALUE" sets the variable NAME to VALUE and each "--SWITCH"
# sets SWITCH to 1; -h/--help prints the header comment and exits 0;
# anything else exits 2. Where the switch list holds "--", a "--" ends the
# options and the arguments after it are left in the array `rest`.
parse_options() {
  local values=" $1 " switches=" $2 " name
  shift 2
  rest=()
  while (($#)); do
    name=${1#--}
    if [[ $1 == -h || $1 == --help ]]; then
      script_help; exit 0
    elif [[ $1 == -- && $switches == *" -- "* ]]; then
      shift; rest=("$@"); return
    elif [[ $1 == --?* && $values == *" $name "* && $# -ge 2 ]]; then
      printf -v "$name" '%s' "$2"; shift 2
    elif [[ $1 == --?* && $switches == *" $name "* ]]; then
      printf -v "$name" 1; shift
    else
      echo "$(basename "$0"): unknown argument '$1' (see --help)" >&2; exit 2
    fi
  done
}

# Exits 2 naming the first argument that is not a whole number.
require_numbers() {
  local n
  for n; do
    [[ "$n" =~ ^[0-9]+$ ]] || { echo "not a number: '$n'" >&2; exit 2; }
  done
}

# Exits 1 naming the first of the apps build/bin/APP ... not built.
require_apps() {
  local app
  for app; do
    [[ -x "build/bin/$app" ]] || {
      echo "$(basename "$0"): build/bin/$app missing: run scripts/setup.sh" >&2
      exit 1; }
  done
}
