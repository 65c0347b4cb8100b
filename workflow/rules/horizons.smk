rule horizons:
    """The case's horizons on their lattice, ordered (erode/onlap/error)."""
    input:
        case=case_file,
    output:
        horizons=out("horizons"),
    log:
        f"{RESULTS}/logs/{{case}}/horizons.log",
    benchmark:
        f"{RESULTS}/benchmarks/{{case}}/horizons.tsv"
    wildcard_constraints:
        case=KEPT,
    conda:
        "../envs/gridlib.yaml"
    threads: 1
    resources:
        mem_mb=2000,
    script:
        "../scripts/horizons.py"


use rule horizons as horizons_temp with:
    output:
        horizons=temp(out("horizons")),
    wildcard_constraints:
        case=DROPPED,
