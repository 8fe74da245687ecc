# Every public header compiles alone, as C11 and as C++17.
get_property(PC_PUBLIC_HEADERS GLOBAL PROPERTY PC_PUBLIC_HEADERS) # the layers' HEADERS lists
set(hdr_srcs)
foreach(h ${PC_PUBLIC_HEADERS})
  get_filename_component(hn ${h} NAME_WE)
  get_filename_component(layer_dir ${h} DIRECTORY)
  foreach(lang c cpp)
    set(f ${CMAKE_CURRENT_BINARY_DIR}/header_${hn}.${lang})
    file(CONFIGURE OUTPUT ${f} CONTENT "#include \"polarcam/${hn}.h\"\nint pc_header_${hn}_${lang}_dummy;\n")
    list(APPEND hdr_srcs ${f})
  endforeach()
endforeach()
add_library(test_headers_alone OBJECT ${hdr_srcs})
target_link_libraries(test_headers_alone PRIVATE pc_core pc_io pc_sim pc_calib pc_devices)
target_compile_options(test_headers_alone PRIVATE $<$<COMPILE_LANGUAGE:C>:-Wno-missing-prototypes -Wno-missing-variable-declarations>)
# Built as part of `all`: a header that does not compile alone fails the build.
