rule transmissibility:
    """Connections (cell pairs, T, kind, face), pore volumes and the simulator's cell index."""
    input:
        unpack(optional("grdecl", lambda c: c.writes_grdecl)),
        case=case_file,
        grid=out("grid"),
        geometry=out("geometry"),
        petrophysics=out("petrophysics"),
    output:
        transmissibility=out("transmissibility"),
    log:
        f"{RESULTS}/logs/{{case}}/transmissibility.log",
    benchmark:
        f"{RESULTS}/benchmarks/{{case}}/transmissibility.tsv"
    wildcard_constraints:
        case=stage_cases(lambda c: c.has_transmissibility, True),
    conda:
        "../envs/gridlib.yaml"
    threads: 1
    resources:
        mem_mb=4000,
    script:
        "../scripts/transmissibility.py"


use rule transmissibility as transmissibility_temp with:
    output:
        transmissibility=temp(out("transmissibility")),
    wildcard_constraints:
        case=stage_cases(lambda c: c.has_transmissibility, False),
