#!/usr/bin/env bash
# The real-asset corpus (issue 20, item 11): every .gltf/.glb of Debian's assimp-testmodels glTF2 folder (Khronos
# sample and test assets, a morphing cube and a skin among them, and files broken on purpose) and the project's
# analytic meshes (data/*.ply, and data/morph-sphere.glb: a sphere with an animated ellipsoid target) go through
# `resurf lod` into a folder other than their own, once as .glb (Draco, the default) and
# once as .gltf (plain accessors, images copied beside it). The Khronos validator judges inputs and outputs.
#   - An input the validator passes must give an output with 0 errors and no more warnings than the input had (or,
#     when it requires extensions, may be refused as below).
#   - An input that breaks the schema (wrong JSON types, a required property missing, a value out of its list) must
#     fail with one line on stderr naming the input file.
#   - Any other input fails the same way or gives an output with no kind of validator error the input lacks (an
#     error of the content that resurf carries over into every level, such as a material that needs tangents the
#     file lacks, may repeat).
#   - Every output: no byte of a buffer that nothing refers to (tests/gltf_dead_bytes.js), and each level has fewer
#     triangles than the one before (from `resurf lod --json`).
# The project's skinned test asset (the two-bone cylinder of tools/skinned_cylinder.h, float and normalized-byte
# weights, bent by its pose) joins them when GEN_ANALYTIC is given, and so do gltfpack's outputs of every valid
# input (EXT_ and KHR_meshopt_compression, KHR_mesh_quantization, EXT_mesh_gpu_instancing), which must not be
# refused.
# usage: test_corpus_gltf.sh RESURF SOURCE_ROOT [GEN_ANALYTIC]      (RESURF_CORPUS_DIR overrides the assets' folder)
set -uo pipefail
resurf=$1
root=$2
gen=${3:-}
models=${RESURF_CORPUS_DIR:-/usr/share/assimp/models/glTF2}
if [ ! -d "$models" ]; then
    echo "corpus: $models is missing (tools/setup.sh installs Debian's assimp-testmodels)"
    exit 1
fi
validate() { node "$root/tools/validate-gltf.js" "$@"; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
failures=0
fail() {
    echo "FAIL $*"
    failures=$((failures + 1))
}

mapfile -t inputs < <(find "$models" \( -name '*.gltf' -o -name '*.glb' \) | sort)
inputs+=("$root/data/morph-sphere.glb") # the analytic morph (tools/morph_asset.h): one animated target
if [ -n "$gen" ]; then
    "$gen" --skinned-cylinder "$work/skinned-cylinder.glb" &&
        "$gen" --skinned-cylinder "$work/skinned-cylinder-ubyte.glb" --ubyte-weights ||
        { echo "corpus: $gen cannot write the skinned cylinder"; exit 1; }
    inputs+=("$work/skinned-cylinder.glb" "$work/skinned-cylinder-ubyte.glb")
fi
# What the peers make of the valid ones, as a pipeline hands them on (gltfpack 1.3, installed by tools/setup.sh):
# meshopt-compressed and quantized (-c), with filters and GPU instancing (-cc -mi), with fallback buffers (-cf),
# and as KHR_meshopt_compression (-cc -ce khr: version 1 of the attribute bitstream, the colour filter).
# These must never be refused.
gltfpack="$root/tools/node/node_modules/gltfpack/cli.js"
if [ ! -f "$gltfpack" ]; then
    echo "corpus: $gltfpack is missing (tools/setup.sh installs gltfpack)"
    exit 1
fi
validate "${inputs[@]}" > "$work/inputs.txt" 2>&1
status=$?
if [ $status -ge 2 ]; then
    echo "corpus: the validator cannot run:"
    cat "$work/inputs.txt"
    exit 1
fi
mkdir -p "$work/peer"
peers=()
for input in "${inputs[@]}"; do
    grep -qF "$input: numErrors 0 " "$work/inputs.txt" || continue
    base=$(basename "${input%.*}")
    for variant in "c:-c" "cc-mi:-cc -mi" "cf:-cf" "cc-khr:-cc -ce khr"; do
        out="$work/peer/${base}-${variant%%:*}.gltf"
        # shellcheck disable=SC2086 # the variant's options are words
        if node "$gltfpack" -i "$input" -o "$out" ${variant#*:} > /dev/null 2>&1; then
            peers+=("$out")
        fi
    done
done
if ! validate "${peers[@]}" >> "$work/inputs.txt" 2>&1 && [ $? -ge 2 ]; then
    echo "corpus: the validator cannot run on gltfpack's outputs"
    exit 1
fi
inputs+=("${peers[@]}")
for shape in sphere torus cubic; do
    inputs+=("$root/data/$shape.ply")
done

# "FILE: numErrors N numWarnings M" of FILE in a validator listing, and the codes of its errors.
counts() { grep -F "$1: numErrors " "$2" | sed 's/.*numErrors \([0-9]*\) numWarnings \([0-9]*\).*/\1 \2/'; }
codes() { awk -v f="$1: numErrors" 'index($0, f) == 1 { on = 1; next } /^[^ ]/ { on = 0 } on { print $1 }' "$2"; }
schema_codes='^(INVALID_INDEX|TYPE_MISMATCH|ARRAY_TYPE_MISMATCH|UNDEFINED_PROPERTY|VALUE_NOT_IN_LIST|INVALID_JSON|INVALID_JSON_ROOT_OBJECT)$'

# Under sanitizers and valgrind (RESURF_TEST_LIGHT=1) the .glb outputs alone, and no input over 200 kB (with its
# buffers): the same readers and checks, a fraction of the time (the release run takes every input).
formats="glb gltf"
light=0
[ "${RESURF_TEST_LIGHT:-0}" = 1 ] && formats=glb light=1

n=0 valid=0 refused=0 written=0 skipped=0
for input in "${inputs[@]}"; do
    n=$((n + 1))
    name=$(basename "${input%.*}")
    if [ $light = 1 ] && [ $(du -cb "$input" "$(dirname "$input")"/*.bin 2>/dev/null | tail -1 | cut -f1) -gt 200000 ]; then
        skipped=$((skipped + 1))
        continue
    fi
    read -r in_errors in_warnings < <(counts "$input" "$work/inputs.txt")
    case "$input" in *.ply) in_errors=0 in_warnings=0 ;; esac
    must_fail=0
    if codes "$input" "$work/inputs.txt" | grep -Eq "$schema_codes"; then
        must_fail=1
    fi
    [ "${in_errors:-1}" = 0 ] && valid=$((valid + 1))
    input_formats=$formats
    [[ $input == "$work/peer/"* ]] && input_formats=glb # the reader is what they test: one output format is enough
    for ext in $input_formats; do
        out="$work/$n-$ext/$name.$ext"
        mkdir -p "$work/$n-$ext"
        if "$resurf" lod "$input" -o "$out" --levels 0.5,0.25 --json > "$work/$n-$ext/report.json" \
            2> "$work/$n-$ext/stderr"; then
            if [ $must_fail = 1 ]; then
                fail "$input ($ext): breaks the glTF schema, yet resurf lod accepted it"
            fi
            written=$((written + 1))
            validate "$out" > "$work/$n-$ext/validator.txt" 2>&1
            read -r out_errors out_warnings < <(counts "$out" "$work/$n-$ext/validator.txt")
            new_codes=$(comm -23 <(codes "$out" "$work/$n-$ext/validator.txt" | sort -u) \
                <(codes "$input" "$work/inputs.txt" | sort -u) | tr '\n' ' ')
            if [ "${out_errors:-1}" -gt 0 ] && [ "${in_errors:-1}" = 0 -o -n "$new_codes" ]; then
                fail "$input ($ext): the output has ${out_errors:-?} validator errors (new: ${new_codes:-none}), the input ${in_errors:-?}:"
                sed -n '1,6p' "$work/$n-$ext/validator.txt"
            else
                if [ "${in_errors:-1}" = 0 ] && [ "${out_warnings:-0}" -gt "${in_warnings:-0}" ]; then
                    fail "$input ($ext): $out_warnings validator warnings on the output, $in_warnings on the input"
                    sed -n '2,6p' "$work/$n-$ext/validator.txt"
                fi
            fi
            if ! node "$root/tests/gltf_dead_bytes.js" "$out" > "$work/$n-$ext/dead.txt" 2>&1; then
                fail "$input ($ext): dead bytes in the output:"
                sed -n '1,4p' "$work/$n-$ext/dead.txt"
            fi
            triangles=$(node -e 'for (const l of JSON.parse(require("fs").readFileSync(process.argv[1])).levels)
                                     console.log(l.triangles)' "$work/$n-$ext/report.json" | tr '\n' ' ')
            previous=
            for t in $triangles; do
                if [ -n "$previous" ] && [ "$t" -ge "$previous" ]; then
                    fail "$input ($ext): a level of $t triangles after one of $previous (levels: $triangles)"
                    break
                fi
                previous=$t
            done
            # The morph asset gets its levels, each with its target, and its animation drives every level node.
            if [ "$name" = morph-sphere ] && ! node -e '
                const fs = require("fs"), p = process.argv[1], b = fs.readFileSync(p);
                const d = JSON.parse(b.slice(0, 4).toString() === "glTF" ? b.slice(20, 20 + b.readUInt32LE(12)).toString()
                                                                         : b.toString());
                const ids = d.nodes[0].extensions.MSFT_lod.ids;
                const driven = d.animations[0].channels.filter(c => c.target.path === "weights").map(c => c.target.node);
                process.exit(ids.length === 2 && [0, ...ids].every(n => driven.includes(n)) &&
                             d.meshes.every(m => m.primitives[0].targets.length === 1) ? 0 : 1)' "$out"; then
                fail "$input ($ext): the morph asset lost its levels, targets or animated weights (levels: $triangles)"
            fi
        else
            refused=$((refused + 1))
            peer=0
            [[ $input == "$work/peer/"* ]] && peer=1
            if [ "${in_errors:-1}" = 0 ] && { [ $peer = 1 ] || ! grep -q '"extensionsRequired"' "$input"; }; then
                fail "$input ($ext): valid input, yet resurf lod failed: $(head -c 300 "$work/$n-$ext/stderr")"
            fi
            lines=$(wc -l < "$work/$n-$ext/stderr")
            if [ "$lines" != 1 ] || ! grep -qF "$input" "$work/$n-$ext/stderr"; then
                fail "$input ($ext): a failure must be one line naming the input; stderr was:"
                head -n 5 "$work/$n-$ext/stderr"
            fi
            if [ -n "$(ls -A "$work/$n-$ext" | grep -v -e '^report.json$' -e '^stderr$')" ]; then
                fail "$input ($ext): a failed run left files: $(ls "$work/$n-$ext" | tr '\n' ' ')"
            fi
        fi
    done
done
echo "corpus: $n inputs ($skipped left to the release run, $valid valid), $written outputs written and checked, $refused runs refused; $failures failures"
[ $failures = 0 ]
