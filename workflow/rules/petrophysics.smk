rule petrophysics:
    """Porosity, permeability and NTG per cell (random fields in depositional coordinates)."""
    input:
        case=case_file,
        grid=out("grid"),
        geometry=out("geometry"),
    output:
        petrophysics=out("petrophysics"),
    log:
        f"{RESULTS}/logs/{{case}}/petrophysics.log",
    benchmark:
        f"{RESULTS}/benchmarks/{{case}}/petrophysics.tsv"
    wildcard_constraints:
        case=KEPT,
    conda:
        "../envs/gridlib.yaml"
    threads: 1
    resources:
        mem_mb=4000,
    script:
        "../scripts/petrophysics.py"


use rule petrophysics as petrophysics_temp with:
    output:
        petrophysics=temp(out("petrophysics")),
    wildcard_constraints:
        case=DROPPED,
