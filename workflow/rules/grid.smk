rule grid:
    """Build the case's grid and check every invariant."""
    input:
        unpack(optional("horizons", lambda c: c.has_horizons)),
        case=case_file,
    output:
        grid=out("grid"),
    log:
        f"{RESULTS}/logs/{{case}}/grid.log",
    benchmark:
        f"{RESULTS}/benchmarks/{{case}}/grid.tsv"
    wildcard_constraints:
        case=stage_cases(lambda c: not c.writes_grdecl, True),
    conda:
        "../envs/gridlib.yaml"
    threads: 1
    resources:
        mem_mb=4000,
    script:
        "../scripts/grid.py"


rule grid_grdecl:
    """Corner-point and deck grids: the grid, checked, and its GRDECL for simulators."""
    input:
        unpack(optional("horizons", lambda c: c.has_horizons)),
        case=case_file,
    output:
        grid=out("grid"),
        grdecl=out("grdecl"),
    log:
        f"{RESULTS}/logs/{{case}}/grid.log",
    benchmark:
        f"{RESULTS}/benchmarks/{{case}}/grid.tsv"
    wildcard_constraints:
        case=stage_cases(lambda c: c.writes_grdecl, True),
    conda:
        "../envs/gridlib.yaml"
    threads: 1
    resources:
        mem_mb=4000,
    script:
        "../scripts/grid.py"


use rule grid as grid_temp with:
    output:
        grid=temp(out("grid")),
    wildcard_constraints:
        case=stage_cases(lambda c: not c.writes_grdecl, False),


use rule grid_grdecl as grid_grdecl_temp with:
    output:
        grid=temp(out("grid")),
        grdecl=out("grdecl"),
    wildcard_constraints:
        case=stage_cases(lambda c: c.writes_grdecl and not c.writes_flow_deck, False),


# The Flow deck's GRID include holds the same grid (with the rock): grid.grdecl is a stage file.
use rule grid_grdecl as grid_grdecl_deck_temp with:
    output:
        grid=temp(out("grid")),
        grdecl=temp(out("grdecl")),
    wildcard_constraints:
        case=stage_cases(lambda c: c.writes_grdecl and c.writes_flow_deck, False),
