#!/bin/sh
# readme.sh: the README's generated blocks are the program's own output.
# A block is
#     <!-- generated: rodsim ARGS -->            (output in a ```text fence)
#     <!-- generated markdown: rodsim ARGS -->   (output as it is: Markdown)
#     ...
#     <!-- end generated -->
# usage: sh tests/readme.sh update RODSIM_BIN [README]   rewrite every block (make readme)
#        sh tests/readme.sh check RODSIM_BIN [README]    one line per block: "same: ARGS" or
#                                                        "differs: ARGS ..."; exit 1 if any differs
# (tests/cli/test_readme.c runs the check under make test.)
mode=$1
bin=$2
readme=${3:-README.md}
case "$mode" in update|check) ;; *) echo "usage: $0 update|check RODSIM_BIN [README]" >&2; exit 2;; esac
[ -x "$bin" ] || { echo "readme.sh: $bin is not an executable" >&2; exit 2; }
[ -f "$readme" ] || { echo "readme.sh: no $readme" >&2; exit 2; }
tmp=$(mktemp) || exit 1
awk -v mode="$mode" -v bin="$bin" -v readme="$readme" '
function run(args,    cmd, line, n, status) {
    cmd = "\"" bin "\" " args " 2>&1; echo \"readme-sh-exit:$?\""
    n = 0
    while ((cmd | getline line) > 0) out[++n] = line
    close(cmd)
    status = out[n]
    sub(/^readme-sh-exit:/, "", status)
    n--
    return status == "0" ? n : -1
}
function report(args, start,    i, g, o, gen) {
    g = 0
    if (!markdown) gen[++g] = "```text"
    for (i = 1; i <= nout; i++) gen[++g] = out[i]
    if (!markdown) gen[++g] = "```"
    if (mode == "update") {
        for (i = 1; i <= g; i++) print gen[i]
        return
    }
    for (i = 1; i <= norig; i++) print orig[i]
    for (i = 1; i <= (g > norig ? g : norig); i++) {
        if (gen[i] != orig[i] || i > g || i > norig) {
            printf "differs: rodsim %s (%s line %d): README has \"%s\", the program prints \"%s\"; run make readme\n", \
                args, readme, start + i, (i <= norig ? orig[i] : "(end of block)"), \
                (i <= g ? gen[i] : "(end of output)") > "/dev/stderr"
            bad++
            return
        }
    }
    printf "same: rodsim %s\n", args > "/dev/stderr"
}
BEGIN { inside = 0; bad = 0; blocks = 0 }
{
    if (!inside && match($0, /^<!-- generated( markdown)?: rodsim .* -->$/)) {
        print
        markdown = ($0 ~ /^<!-- generated markdown:/)
        args = $0
        sub(/^<!-- generated( markdown)?: rodsim /, "", args)
        sub(/ -->$/, "", args)
        start = NR
        norig = 0
        inside = 1
        blocks++
        nout = run(args)
        if (nout < 0) {
            printf "differs: rodsim %s (%s line %d): the command failed\n", args, readme, NR > "/dev/stderr"
            bad++
            nout = 0
        }
        next
    }
    if (inside && $0 == "<!-- end generated -->") {
        report(args, start)
        print
        inside = 0
        next
    }
    if (inside) { orig[++norig] = $0; next }
    print
}
END {
    if (inside) { printf "differs: rodsim %s: no <!-- end generated --> line\n", args > "/dev/stderr"; bad++ }
    printf "%d generated blocks, %d differ\n", blocks, bad > "/dev/stderr"
    exit bad > 0 ? 1 : 0
}' "$readme" >"$tmp"
status=$?
if [ "$mode" = update ] && [ $status -eq 0 ]; then
    cmp -s "$tmp" "$readme" || cat "$tmp" >"$readme"
fi
rm -f "$tmp"
exit $status
