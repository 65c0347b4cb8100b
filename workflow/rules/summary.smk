rule summary:
    """Every case's figures in one table."""
    input:
        expand(f"{RESULTS}/{{case}}/summary.json", case=sorted(CASES)),
    output:
        csv=report(
            f"{RESULTS}/summary.csv",
            caption="../report/summary.rst",
            category=artifacts.SUMMARY,
        ),
    log:
        f"{RESULTS}/logs/summary.log",
    benchmark:
        f"{RESULTS}/benchmarks/summary.tsv"
    conda:
        "../envs/gridlib.yaml"
    threads: 1
    resources:
        mem_mb=1000,
    script:
        "../scripts/summary.py"
