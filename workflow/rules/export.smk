rule export_vtu:
    """The grid with its geometry as cell data, for ParaView/pyvista."""
    input:
        case=case_file,
        grid=f"{RESULTS}/{{case}}/grid.nc",
        geometry=f"{RESULTS}/{{case}}/geometry.nc",
    output:
        vtu=f"{RESULTS}/{{case}}/{{case}}.vtu",
    log:
        f"{RESULTS}/logs/{{case}}/export_vtu.log",
    benchmark:
        f"{RESULTS}/benchmarks/{{case}}/export_vtu.tsv"
    conda:
        "../envs/gridlib.yaml"
    threads: 1
    resources:
        mem_mb=4000,
    script:
        "../scripts/export_vtu.py"
