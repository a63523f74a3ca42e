# tests/labels.cmake - the ctest labels of every test (CONTRIBUTING.md, "Tests"):
#   unit    one module's library code on constructed or small real inputs; together
#           they cover every module, and `ctest -L unit` is the quick subset
#   e2e     the planetgen command end to end on real data
#   client  a real client tool reads our output (Blender, f3d, the glTF validator,
#           Chromium)
#   mpi     mpirun with several ranks
#   slow    many minutes natively (the realism report's 8 planets, the texture
#           comparison on the real exemplar)
# The sanitizer pass of CI runs `-L unit` (scripts/ci-extra): that is why every module
# needs at least one unit test, the planet module's being test_generate (planet
# synthesis through the library on the real exemplar) and the mpi module's
# test_mpi_pits (the distributed pit removal against the serial one, on 1 to 4 ranks).
# A test file missing here stops the configure, so no test goes unlabelled.

set(PG_LABEL_unit
    test_cli_watcher test_core_helpers test_cube_adjacency test_cube_distortion
    test_cube_geodesy test_cube_halo test_cube_projection test_cube_resample test_drainage
    test_earthlike test_exemplar test_export_mesh test_generate test_image_io
    test_inspect_copy test_inspect_distortion test_inspect_seams test_lpips test_mpi_pits
    test_pits_cube test_pits_gainpit test_pits_grid test_planet test_readme_table
    test_synth_engine test_synth_grid_shape test_plates test_climate)
set(PG_LABEL_e2e
    test_bad_input test_cli test_cube_cli test_determinism test_export_cli test_generate_cli
    test_inspect test_install test_pits_cli test_pits_gdal test_pits_relief test_realism_e2e
    test_resource_limits test_synth_cli test_synth_quality test_export_blender test_export_f3d
    test_export_geotiff test_export_gltf test_export_tiles test_mpi_generate test_world test_view)
set(PG_LABEL_client test_export_blender test_export_f3d test_export_gltf test_export_tiles test_view)
set(PG_LABEL_mpi test_export_tiles test_mpi_generate test_mpi_pits)
set(PG_LABEL_slow test_realism_e2e test_inspect)

# pg_test_labels(NAME): give test NAME its labels from the lists above.
function(pg_test_labels name)
  set(labels "")
  foreach(l unit e2e client mpi slow)
    if(name IN_LIST PG_LABEL_${l})
      list(APPEND labels ${l})
    endif()
  endforeach()
  if(NOT labels)
    message(FATAL_ERROR "${name} has no ctest label: add it to tests/labels.cmake")
  endif()
  set_tests_properties(${name} PROPERTIES LABELS "${labels}")
endfunction()
