#!/usr/bin/env bash
# Checks the machine-checked guarantees in proofs/ (Coq, Debian package `coq`, 8.16):
#
#   1. every theory file under theories/ is listed in _CoqProject and compiles;
#   2. no file contains an unfinished proof or a declared assumption: Admitted, admit,
#      give_up, Axiom(s), Parameter(s), Hypothesis/Hypotheses, Conjecture, or switches
#      that turn the kernel's checks off (comments and strings are ignored);
#   3. `Print Assumptions` of every Theorem/Lemma/Corollary/Proposition/Fact/Remark/Example
#      lists only the axioms of the standard library's real numbers (ALLOWED_AXIOMS below).
#
# Usage: bash proofs/check.sh     (from anywhere; about 25 s of CPU from scratch)
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")"

# The axioms Coq 8.16's Reals library rests on: Rdefinitions builds R from Dedekind cuts
# with the limited principle of omniscience (sig_forall_dec) and sig_not_dec, and uses
# functional extensionality. Everything in Reals that is axiom-free beyond these (sin, cos,
# completeness, Rle_dec, ...) is allowed; Classical_Prop.classic (used by the stdlib's MVT
# and sin_lt_x) is not.
ALLOWED_AXIOMS=(
    ClassicalDedekindReals.sig_forall_dec
    ClassicalDedekindReals.sig_not_dec
    FunctionalExtensionality.functional_extensionality_dep
)

fail() { printf 'proofs: FAIL: %s\n' "$*" >&2; exit 1; }
log() { printf 'proofs: %s\n' "$*" >&2; }

command -v coqc >/dev/null && command -v coq_makefile >/dev/null ||
    fail "coqc/coq_makefile not found: install the Debian package coq (bash setup.sh does)"

mapfile -t listed < <(grep -E '^theories/.*\.v$' _CoqProject)
mapfile -t present < <(find theories -name '*.v' | sort)
for f in "${present[@]}"; do
    printf '%s\n' "${listed[@]}" | grep -qxF "$f" || fail "$f is not listed in _CoqProject"
done

# 1. Compile (incrementally; coq_makefile's build files are git-ignored).
coq_makefile -f _CoqProject -o CoqMakefile >/dev/null
make -s -f CoqMakefile -j2 >&2 || fail "compilation failed"

# Source text without comments and strings, for the scans below.
strip() {
    perl -0777 -pe 's/"(?:[^"]|"")*"/""/g; 1 while s/\(\*(?:(?!\(\*|\*\)).)*?\*\)/ /gs' "$1"
}

# 2. Forbidden vernacular.
forbidden='\b(Admitted|admit|give_up|Axioms?|Parameters?|Hypothes[ie]s|Conjecture|Admit Obligations|Unset (Guard|Positivity|Universe) Checking|bypass_check)\b'
for f in "${listed[@]}"; do
    if hits=$(strip "$f" | grep -nE "$forbidden"); then
        fail "$f contains a forbidden command:"$'\n'"$hits"
    fi
done

# 3. Print Assumptions of every named result. One Print Assumptions costs about a second
#    (it walks the construction of R each time), so all results are bundled into one
#    definition first; only if that shows a foreign axiom is each result printed on its own,
#    to name the culprits.
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
results=()
header="From Coq Require Reals."
for f in "${listed[@]}"; do
    mod="KinScene.$(sed -e 's|^theories/||' -e 's|\.v$||' -e 's|/|.|g' <<<"$f")"
    header+=$'\n'"Require $mod."
    while read -r name; do
        results+=("$mod.$name")
    done < <(strip "$f" |
        perl -ne 'print "$2\n" if /^\s*(Theorem|Lemma|Corollary|Proposition|Fact|Remark|Example)\s+([A-Za-z_][A-Za-z0-9_'"'"']*)/')
done
[ "${#results[@]}" -gt 0 ] || fail "no theorems found"

# Prints the axioms (one name a line) that `Print Assumptions` output file $1 lists.
axioms_in() {
    # Axiom lines start at column 0; continuation lines of their types are indented.
    grep -E '^[^[:space:]]' "$1" | grep -vxE 'Axioms:|Closed under the global context' |
        sed -E 's/[[:space:]]*:.*$//' || true
}
# Prints the axioms of output file $1 that are not allowed.
foreign_axioms() {
    local axiom a ok
    while read -r axiom; do
        ok=0
        for a in "${ALLOWED_AXIOMS[@]}"; do
            [[ "$axiom" == "$a" || "$axiom" == *".$a" ]] && ok=1
        done
        [ "$ok" -eq 1 ] || printf '%s\n' "$axiom"
    done < <(axioms_in "$1")
}

{
    printf '%s\n' "$header"
    printf 'Definition kinscene_all_results := (tt'
    printf ', @%s' "${results[@]}"
    printf ').\nRedirect "%s/all" Print Assumptions kinscene_all_results.\n' "$tmp"
} >"$tmp/All.v"
coqc -R theories KinScene "$tmp/All.v" >&2 || fail "Print Assumptions failed"
[ -s "$tmp/all.out" ] || fail "Print Assumptions printed nothing"
if [ -n "$(foreign_axioms "$tmp/all.out")" ]; then
    {
        printf '%s\n' "$header"
        for r in "${results[@]}"; do
            printf 'Redirect "%s/one-%s" Print Assumptions %s.\n' "$tmp" "$r" "$r"
        done
    } >"$tmp/Each.v"
    coqc -R theories KinScene "$tmp/Each.v" >&2 || fail "Print Assumptions failed"
    for r in "${results[@]}"; do
        while read -r axiom; do
            printf 'proofs: %s depends on the axiom %s\n' "$r" "$axiom" >&2
        done < <(foreign_axioms "$tmp/one-$r.out")
    done
    fail "axioms outside the allowed list (${ALLOWED_AXIOMS[*]})"
fi
log "ok: ${#listed[@]} files, ${#results[@]} results, axioms within {${ALLOWED_AXIOMS[*]}}"
