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
    conda:
        "../envs/gridlib.yaml"
    threads: 1
    resources:
        mem_mb=2000,
    script:
        "../scripts/horizons.py"
