rule export:
    """One self-describing netCDF, VTU, fault faces, pictures and the case's summary."""
    input:
        unpack(optional("petrophysics", lambda c: c.has_petrophysics)),
        unpack(optional("coarse", lambda c: c.has_coarsening)),
        unpack(optional("transmissibility", lambda c: c.has_transmissibility)),
        case=case_file,
        grid=out("grid"),
        geometry=out("geometry"),
    output:
        nc=out("nc"),
        vtu=out("vtu"),
        faults=out("faults"),
        png=report(
            out("png"),
            caption="../report/grid.rst",
            category="Grids",
            subcategory="{case}",
        ),
        histograms=report(
            out("histograms"),
            caption="../report/histograms.rst",
            category="Grids",
            subcategory="{case}",
        ),
        summary=out("summary"),
    log:
        f"{RESULTS}/logs/{{case}}/export.log",
    benchmark:
        f"{RESULTS}/benchmarks/{{case}}/export.tsv"
    wildcard_constraints:
        case=WITH_VTU,
    conda:
        "../envs/gridlib.yaml"
    threads: 1
    resources:
        mem_mb=4000,
    script:
        "../scripts/export.py"


use rule export as export_without_vtu with:
    output:
        nc=out("nc"),
        faults=out("faults"),
        png=report(
            out("png"),
            caption="../report/grid.rst",
            category="Grids",
            subcategory="{case}",
        ),
        histograms=report(
            out("histograms"),
            caption="../report/histograms.rst",
            category="Grids",
            subcategory="{case}",
        ),
        summary=out("summary"),
    wildcard_constraints:
        case=WITHOUT_VTU,
