# The library's sources (paths relative to kernels/), shared by kernels/CMakeLists.txt and the fuzz
# targets' own project (tests/fuzz/targets), which compiles them again, instrumented.
#
# beamtrace_isa_unit(ISA FLAGS...): kernels/simd/kernels_ISA.cpp, the one translation unit compiled
# for that instruction set. It fills every kernel table of the ISA (simd/dispatch.hpp) and is the only
# unit that instantiates xsimd templates for it, so no inline function compiled for a wider ISA can
# be picked by the linker for a narrower one. BEAMTRACE_KERNELS_DIR: the kernels folder.
set(BEAMTRACE_ISA_SOURCES "")
function(beamtrace_isa_unit isa)
  set(unit ${BEAMTRACE_KERNELS_DIR}/simd/kernels_${isa}.cpp)
  set_source_files_properties(${unit} PROPERTIES COMPILE_OPTIONS "${ARGN}")
  set(BEAMTRACE_ISA_SOURCES ${BEAMTRACE_ISA_SOURCES} ${unit} PARENT_SCOPE)
endfunction()
beamtrace_isa_unit(sse42 -msse4.2)
beamtrace_isa_unit(avx2 -mavx2 -mfma)
beamtrace_isa_unit(avx512 -mavx512f -mavx512cd -mavx512dq -mavx512bw -mavx512vl -mavx2 -mfma)

set(BEAMTRACE_SOURCES ${BEAMTRACE_ISA_SOURCES})
foreach(source
    simd/isa.cpp
    common/scene.cpp
    animation/animated_scene.cpp
    common/ray.cpp
    common/ray_validity.cpp
    common/watertight_packet.cpp
    common/triangle_reference.cpp
    common/triangle_kernels.cpp
    kdtree/build_rules.cpp
    kdtree/split_events.cpp
    kdtree/build_context.cpp
    kdtree/event_sweep_builder.cpp
    kdtree/reference_bins.cpp
    kdtree/binned_builder.cpp
    kdtree/sah_builder.cpp
    kdtree/kd_traversal.cpp
    kdtree/kd_queries.cpp
    kdtree/brute_force.cpp
    kdtree/packet/lane_box_test.cpp
    kdtree/packet/packet_bounds.cpp
    kdtree/packet/one_origin_frustum.cpp
    kdtree/packet/packet_kernels.cpp
    kdtree/packet/packet_lanes.cpp
    kdtree/packet/packet_set_ranges.cpp
    kdtree/packet/packet_tables.cpp
    kdtree/packet/packet_traversal.cpp
    vlf/directions/direction_set.cpp
    vlf/build/tile_bsp.cpp
    vlf/build/parallel_subfield.cpp
    vlf/build/tile_cache.cpp
    vlf/build/triangle_box_tree.cpp
    vlf/visibility_field.cpp
    vlf/stream/packet_query.cpp
    vlf/stream/ray_stream.cpp
    vlf/query/field_queries.cpp
    vlf/stream/tile_ray_stream.cpp
    vlf/vlf_kernels.cpp
    vlf/build/dynamic_update.cpp
    bvh/wide_bvh_builder.cpp
    bvh/wide_bvh_packet.cpp
    bvh/wide_bvh_traversal.cpp
    stream/ray_keys.cpp
    stream/radix_sort.cpp
    stream/ray_sort.cpp
    stream/ray_groups.cpp
    stream/group_traversal.cpp
    stream/sorted_stream.cpp
    stream/stream_tracer.cpp
    mlrta/beam.cpp
    mlrta/beam_triangles.cpp
    mlrta/covered_leaves.cpp
    mlrta/entry_point_search.cpp
    mlrta/entry_point_trace.cpp
    mlrta/shadow_reversal.cpp
    raycls/cell_beam.cpp
    raycls/candidate_list.cpp
    raycls/direction_grid.cpp
    raycls/cell_tree.cpp
    raycls/ray_classification.cpp
    raycls/moving_bin.cpp
    raycls/space_time_classification.cpp
    mlrta/tile_tracer.cpp
    mlrta/mlrta.cpp
    crsh/bounding_spheres.cpp
    crsh/cone.cpp
    crsh/ray_keys.cpp
    crsh/radix_sort.cpp
    crsh/ray_hierarchy.cpp
    crsh/crsh_impl.cpp
    crsh/traversal.cpp
    crsh/crsh.cpp
    lists/hierarchy_builder.cpp
    lists/list_traversal.cpp
    lists/sorted_lists.cpp
  )
  list(APPEND BEAMTRACE_SOURCES ${BEAMTRACE_KERNELS_DIR}/${source})
endforeach()
