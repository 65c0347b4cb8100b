rule geometry:
    """Cell volumes and centroids, face areas, normals and centroids."""
    input:
        case=case_file,
        grid=out("grid"),
    output:
        geometry=out("geometry"),
    log:
        f"{RESULTS}/logs/{{case}}/geometry.log",
    benchmark:
        f"{RESULTS}/benchmarks/{{case}}/geometry.tsv"
    wildcard_constraints:
        case=KEPT,
    conda:
        "../envs/gridlib.yaml"
    threads: 1
    resources:
        mem_mb=4000,
    script:
        "../scripts/geometry.py"


use rule geometry as geometry_temp with:
    output:
        geometry=temp(out("geometry")),
    wildcard_constraints:
        case=DROPPED,
