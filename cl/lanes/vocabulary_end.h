/* The end of a lane vocabulary's templates (cl/lanes/one_ray.h lists the vocabulary): its
 * names undefined, so that the next vocabulary (cl/lanes/quad.h, cl/lanes/packet.h)
 * defines its own. Listed after each vocabulary's templates in the kernel's sources
 * (CMakeLists.txt RAY_CL_SOURCES). */
#undef RAY_LANE_VOCABULARY
#undef RAY_LANE_SUFFIX
#undef LaneFloat
#undef LaneInt
#undef LaneVec3
#undef laneVec3
#undef laneSelect
#undef laneSelectVec3
#undef laneAny
#undef laneNot
#undef laneEarlyOut
#undef laneAlong
#undef laneDot
#undef laneRowDot
#undef laneCross
#undef RAY_LANES_ARE_TRIANGLES
