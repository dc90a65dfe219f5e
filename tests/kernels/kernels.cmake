# Kernels only the tests dispatch, embedded into megavox_tests alone (cmake/EmbedKernels.cmake, as
# kernels/kernels.cmake for the library): the kernel language's self-tests (lang/, bodies in
# bodies/lang_*.h) and the layout probes (probe/, bodies/layout_probe.h) that check each shared
# struct as every device sees it. Host code names them by TestKernelId (tests/test_kernels.h).
#         name                     .cl               .comp                n  params            GLSL defines
mv_kernel(lang_atomics_k32         lang/lang32.cl    lang/lang.comp       3  MvLangParams      MV_ENTRY_atomics)
mv_kernel(lang_shared_atomics_k32  lang/lang32.cl    lang/lang.comp       2  MvLangParams      MV_ENTRY_shared_atomics)
mv_kernel(lang_histogram           lang/lang32.cl    lang/lang.comp       2  MvLangParams      MV_ENTRY_histogram)
mv_kernel(lang_grid2d              lang/lang32.cl    lang/lang.comp       1  MvLangParams      MV_ENTRY_grid2d)
mv_kernel(lang_args                lang/lang32.cl    lang/lang.comp       6  MvLangArgsParams  MV_ENTRY_args MV_ARGS_BUFFER)
mv_kernel(lang_atomics_k64         lang/lang64.cl    lang/lang.comp       3  MvLangParams      MV_ENTRY_atomics MV_LANG64 NEEDS_ATOMICS64)
mv_kernel(lang_shared_atomics_k64  lang/lang64.cl    lang/lang.comp       2  MvLangParams      MV_ENTRY_shared_atomics MV_LANG64 NEEDS_SHARED_ATOMICS64)
mv_kernel(probe_morton_params      probe/layout.cl   probe/layout.comp    1  MvMortonParams    MV_ENTRY_probe_morton_params)
mv_kernel(probe_radix_params       probe/layout.cl   probe/layout.comp    1  MvRadixParams     MV_ENTRY_probe_radix_params)
mv_kernel(probe_scan_params        probe/layout.cl   probe/layout.comp    1  MvScanParams      MV_ENTRY_probe_scan_params)
mv_kernel(probe_unique_params      probe/layout.cl   probe/layout.comp    1  MvUniqueParams    MV_ENTRY_probe_unique_params)
mv_kernel(probe_cache_params       probe/layout.cl   probe/layout.comp    1  MvCacheParams     MV_ENTRY_probe_cache_params)
mv_kernel(probe_lang_params        probe/layout.cl   probe/layout.comp    1  MvLangParams      MV_ENTRY_probe_lang_params)
mv_kernel(probe_voxelize_params    probe/layout.cl   probe/layout.comp    1  MvVoxelizeParams  MV_ENTRY_probe_voxelize_params)
mv_kernel(probe_dag_params         probe/layout.cl   probe/layout.comp    1  MvDagParams       MV_ENTRY_probe_dag_params)
mv_kernel(probe_trace_params       probe/layout.cl   probe/layout.comp    1  MvTraceParams     MV_ENTRY_probe_trace_params)
mv_kernel(probe_secondary_params   probe/layout.cl   probe/layout.comp    1  MvSecondaryParams MV_ENTRY_probe_secondary_params)
mv_kernel(probe_ray                probe/layout.cl   probe/layout.comp    1  MvRay             MV_ENTRY_probe_ray)
mv_kernel(probe_hit                probe/layout.cl   probe/layout.comp    1  MvHit             MV_ENTRY_probe_hit)
mv_kernel(probe_point_params       probe/layout.cl   probe/layout.comp    1  MvPointParams     MV_ENTRY_probe_point_params)
mv_kernel(probe_splat_params       probe/layout.cl   probe/layout.comp    1  MvSplatParams     MV_ENTRY_probe_splat_params)
mv_kernel(probe_min_cut_params     probe/layout.cl   probe/layout.comp    1  MvMinCutParams    MV_ENTRY_probe_min_cut_params)
mv_kernel(probe_min_cut_regions_params probe/layout.cl probe/layout.comp  1  MvMinCutRegionsParams MV_ENTRY_probe_min_cut_regions_params)
mv_kernel(probe_mask_post_params   probe/layout.cl   probe/layout.comp    1  MvMaskPostParams  MV_ENTRY_probe_mask_post_params)
