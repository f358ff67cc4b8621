#pragma once
// Eigen-decomposition of a small symmetric matrix (n <= 4) by cyclic Jacobi rotations: the
// plane through COLMAP's ring of camera centres (colmap.cpp) and Horn's quaternion for the
// pose alignment (pose_alignment.cpp).

namespace refrax {

struct SymmetricEigen {
  int n = 0;
  double values[4] = {};      // values[k]: the k-th eigenvalue (unsorted)
  double vectors[4][4] = {};  // vectors[.][k]: its unit eigenvector
  int largest() const;        // the index k of the largest eigenvalue
  int smallest() const;
};

// Only the upper-left n x n block of `a` is read; it must be symmetric.
SymmetricEigen symmetricEigen(const double a[4][4], int n);

}  // namespace refrax
