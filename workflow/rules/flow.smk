rule flow_deck:
    """The case's OPM Flow deck flow/<NAME>.DATA and its includes (part of the export; a rule
    of its own because the file is named after the case in upper case, which Snakemake
    cannot derive from {case}: NAME is a second wildcard, checked against the case)."""
    input:
        unpack(optional("grdecl", lambda c: c.writes_grdecl)),
        case=case_file,
        grid=out("grid"),
        geometry=out("geometry"),
        petrophysics=out("petrophysics"),
        transmissibility=out("transmissibility"),
    output:
        deck=f"{RESULTS}/{{case}}/flow/{{NAME}}.DATA",
    log:
        f"{RESULTS}/logs/{{case}}/flow_deck.{{NAME}}.log",
    benchmark:
        f"{RESULTS}/benchmarks/{{case}}/flow_deck.{{NAME}}.tsv"
    wildcard_constraints:
        case=WITH_FLOW_DECK,
        NAME=FLOW_NAMES,
    conda:
        "../envs/gridlib.yaml"
    threads: 1
    resources:
        mem_mb=4000,
    script:
        "../scripts/flow_deck.py"


rule simulate_case:
    """OPM Flow runs the case's deck: its output under flow/, the wells' rates and pressures,
    the field figures, and the results on the case's own grid."""
    input:
        deck=deck_of,
        case=case_file,
        grid=out("grid"),
        transmissibility=out("transmissibility"),
    output:
        summary=f"{RESULTS}/{{case}}/flow/summary.json",
        wells=report(
            f"{RESULTS}/{{case}}/flow/{{case}}_wells.png",
            caption="../report/wells.rst",
            category="Simulations",
            subcategory="{case}",
        ),
        vtu=f"{RESULTS}/{{case}}/flow/{{case}}_flow.vtu",
    log:
        f"{RESULTS}/logs/{{case}}/simulate.log",
    benchmark:
        f"{RESULTS}/benchmarks/{{case}}/simulate.tsv"
    wildcard_constraints:
        case=WITH_SIMULATION,
    conda:
        "../envs/gridlib.yaml"
    threads: 1
    resources:
        mem_mb=4000,
    script:
        "../scripts/simulate.py"


rule simulate:
    """Every case with a `simulation` section through OPM Flow: `snakemake simulate` (or
    `simulate: true` in the configuration, which adds them to `all`)."""
    input:
        simulation_outputs(),
