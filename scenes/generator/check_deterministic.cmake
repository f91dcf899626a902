# Runs scene_generator twice and fails unless both .glb files are identical.
foreach(run a b)
  execute_process(COMMAND ${GENERATOR} --out ${DIR}/deterministic_${run}.glb --detail 1
                  RESULT_VARIABLE rc)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "scene_generator failed (${rc})")
  endif()
endforeach()
execute_process(COMMAND ${CMAKE_COMMAND} -E compare_files ${DIR}/deterministic_a.glb
                        ${DIR}/deterministic_b.glb RESULT_VARIABLE differ)
if(differ)
  message(FATAL_ERROR "two runs of scene_generator wrote different bytes")
endif()
