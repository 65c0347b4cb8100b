rule grid:
    """Build the case's grid and check every invariant."""
    input:
        case=case_file,
    output:
        grid=f"{RESULTS}/{{case}}/grid.nc",
    log:
        f"{RESULTS}/logs/{{case}}/grid.log",
    benchmark:
        f"{RESULTS}/benchmarks/{{case}}/grid.tsv"
    conda:
        "../envs/gridlib.yaml"
    threads: 1
    resources:
        mem_mb=4000,
    script:
        "../scripts/grid.py"
