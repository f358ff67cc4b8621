#include "engine/dataset/symmetric_eigen.h"

#include <cmath>

namespace refrax {

int SymmetricEigen::largest() const {
  int k = 0;
  for (int i = 1; i < n; i++)
    if (values[i] > values[k]) k = i;
  return k;
}

int SymmetricEigen::smallest() const {
  int k = 0;
  for (int i = 1; i < n; i++)
    if (values[i] < values[k]) k = i;
  return k;
}

SymmetricEigen symmetricEigen(const double input[4][4], int n) {
  SymmetricEigen e;
  e.n = n;
  double a[4][4];
  for (int i = 0; i < n; i++)
    for (int j = 0; j < n; j++) {
      a[i][j] = input[i][j];
      e.vectors[i][j] = i == j ? 1 : 0;
    }
  for (int sweep = 0; sweep < 50; sweep++) {
    double off = 0, scale = 0;
    for (int i = 0; i < n; i++)
      for (int j = 0; j < n; j++) (i == j ? scale : off) += a[i][j] * a[i][j];
    if (off <= 1e-30 * scale || off == 0) break;
    for (int p = 0; p < n; p++)
      for (int q = p + 1; q < n; q++) {
        if (a[p][q] == 0) continue;
        double theta = (a[q][q] - a[p][p]) / (2 * a[p][q]);
        double t = (theta >= 0 ? 1 : -1) / (std::abs(theta) + std::sqrt(theta * theta + 1));
        double c = 1 / std::sqrt(t * t + 1), s = t * c;
        for (int k = 0; k < n; k++) {  // columns p, q
          double akp = a[k][p], akq = a[k][q];
          a[k][p] = c * akp - s * akq;
          a[k][q] = s * akp + c * akq;
        }
        for (int k = 0; k < n; k++) {  // rows p, q
          double apk = a[p][k], aqk = a[q][k];
          a[p][k] = c * apk - s * aqk;
          a[q][k] = s * apk + c * aqk;
        }
        for (int k = 0; k < n; k++) {
          double vkp = e.vectors[k][p], vkq = e.vectors[k][q];
          e.vectors[k][p] = c * vkp - s * vkq;
          e.vectors[k][q] = s * vkp + c * vkq;
        }
      }
  }
  for (int i = 0; i < n; i++) e.values[i] = a[i][i];
  return e;
}

}  // namespace refrax
