# Every kernel megavox embeds: name, OpenCL program (.cl, built once per device), GLSL entry (.comp)
# and the defines that pick the entry and the key type out of the .comp. Names are the OpenCL entry names.
#          name                 .cl                  .comp                    GLSL defines
mv_kernel(radix_or_and_k32      sort/sort.cl         sort/radix_sort.comp     MV_ENTRY_or_and)
mv_kernel(radix_or_and_k64      sort/sort.cl         sort/radix_sort.comp     MV_ENTRY_or_and MV_KEY64)
mv_kernel(radix_histogram_k32   sort/sort.cl         sort/radix_sort.comp     MV_ENTRY_histogram)
mv_kernel(radix_histogram_k64   sort/sort.cl         sort/radix_sort.comp     MV_ENTRY_histogram MV_KEY64)
mv_kernel(radix_scatter_k32     sort/sort.cl         sort/radix_sort.comp     MV_ENTRY_scatter)
mv_kernel(radix_scatter_k64     sort/sort.cl         sort/radix_sort.comp     MV_ENTRY_scatter MV_KEY64)
mv_kernel(scan_reduce           scan/scan.cl         scan/scan.comp           MV_ENTRY_reduce)
mv_kernel(scan_small            scan/scan.cl         scan/scan.comp           MV_ENTRY_small)
mv_kernel(scan_apply            scan/scan.cl         scan/scan.comp           MV_ENTRY_apply)
mv_kernel(morton_encode32       morton/morton.cl     morton/morton.comp)
mv_kernel(morton_encode64       morton/morton.cl     morton/morton.comp       MV_KEY64)
