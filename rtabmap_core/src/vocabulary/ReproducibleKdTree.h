#pragma once
// FLANN's randomised kd-trees, made reproducible (private to the vocabulary area).
//
// Debian's FLANN (1.9) shuffles the points of every tree with a std::mt19937 seeded from
// std::random_device, so two runs over the same images built different trees, found different
// approximate nearest words and, now and then, a different loop closure. The build is FLANN's own
// algorithm (per tree: a random order of the points, then a recursive split on a dimension drawn
// among the RAND_DIM of highest variance, at their mean); only its random numbers change: they
// come from an engine seeded with a constant at each build, so the same words give the same trees.
//
// The mechanism: explicit specialisations of KDTreeIndex's two members that draw random numbers,
// for two distance types that behave as FLANN's L2 and exist only to select them. Everything else
// (insertion of new points, removal, search) is FLANN's unchanged code.
#include <flann/flann.hpp>

namespace rtabmap::vocabulary {

// Binary descriptors expanded one byte per bit (see WordIndex.cpp) and float descriptors.
struct ReproducibleL2Bytes : flann::L2<unsigned char> {};
struct ReproducibleL2Floats : flann::L2<float> {};

}  // namespace rtabmap::vocabulary

namespace flann {

template <>
void KDTreeIndex<rtabmap::vocabulary::ReproducibleL2Bytes>::buildIndexImpl();
template <>
int KDTreeIndex<rtabmap::vocabulary::ReproducibleL2Bytes>::selectDivision(DistanceType* variances);
template <>
void KDTreeIndex<rtabmap::vocabulary::ReproducibleL2Floats>::buildIndexImpl();
template <>
int KDTreeIndex<rtabmap::vocabulary::ReproducibleL2Floats>::selectDivision(DistanceType* variances);

}  // namespace flann
