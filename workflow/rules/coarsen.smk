rule coarsen:
    """Partition, coarse grid and upscaled rock."""
    input:
        unpack(optional("petrophysics", lambda c: c.has_petrophysics)),
        case=case_file,
        grid=out("grid"),
        geometry=out("geometry"),
    output:
        coarse=out("coarse"),
    log:
        f"{RESULTS}/logs/{{case}}/coarsen.log",
    benchmark:
        f"{RESULTS}/benchmarks/{{case}}/coarsen.tsv"
    wildcard_constraints:
        case=KEPT,
    conda:
        "../envs/gridlib.yaml"
    threads: 1
    resources:
        mem_mb=4000,
    script:
        "../scripts/coarsen.py"


use rule coarsen as coarsen_temp with:
    output:
        coarse=temp(out("coarse")),
    wildcard_constraints:
        case=DROPPED,
