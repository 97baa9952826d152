// Pose, link, sensor and calibration blobs (declared in Blobs.h).
#include "Blobs.h"

#include <algorithm>
#include <cstdint>

#include "ByteIO.h"

namespace rtabmap::db::blob {

namespace {

void putTransform(ByteWriter& w, const Transform& t) {
  double values[12];
  t.toArray12(values);
  for (double v : values) w.put(v);
}

Transform getTransform(ByteReader& r) {
  double values[12];
  for (double& v : values) v = r.get<double>();
  return Transform::fromArray12(values);
}

template <typename Matrix>
void putMatrix(ByteWriter& w, const Matrix& m) {
  for (int i = 0; i < m.rows(); ++i)
    for (int j = 0; j < m.cols(); ++j) w.put(static_cast<double>(m(i, j)));
}

template <typename Matrix>
void getMatrix(ByteReader& r, Matrix& m) {
  for (int i = 0; i < m.rows(); ++i)
    for (int j = 0; j < m.cols(); ++j) m(i, j) = r.get<double>();
}

}  // namespace

Bytes encodeTransform(const Transform& t) {
  if (t.isNull()) return {};
  ByteWriter w(96);
  putTransform(w, t);
  return w.take();
}

Transform decodeTransform(const unsigned char* data, size_t size) {
  if (size == 0) return Transform();
  ByteReader r(data, size, "transform");
  Transform t = getTransform(r);
  r.expectEnd();
  return t;
}

Bytes encodeInformation(const Link::InfMatrix& information) {
  const bool diagonal = (information - Link::InfMatrix(information.diagonal().asDiagonal()))
                            .cwiseAbs()
                            .maxCoeff() == 0.0;
  ByteWriter w(diagonal ? 48 : 288);
  if (diagonal) {
    for (int i = 0; i < 6; ++i) w.put(information(i, i));
  } else {
    putMatrix(w, information);
  }
  return w.take();
}

Link::InfMatrix decodeInformation(const unsigned char* data, size_t size) {
  ByteReader r(data, size, "information matrix");
  Link::InfMatrix information = Link::InfMatrix::Zero();
  if (size == 6 * sizeof(double)) {
    for (int i = 0; i < 6; ++i) information(i, i) = r.get<double>();
  } else {
    getMatrix(r, information);
  }
  r.expectEnd();
  return information;
}

Bytes encodeVelocity(const Signature::Velocity& velocity) {
  return encodeArray(std::vector<float>(velocity.begin(), velocity.end()));
}

Signature::Velocity decodeVelocity(const unsigned char* data, size_t size) {
  const std::vector<float> values = decodeArray<float>(data, size, "velocity");
  if (values.size() != 6) throw FormatError("stored velocity has " + std::to_string(values.size()) + " values, not 6");
  Signature::Velocity velocity;
  std::copy(values.begin(), values.end(), velocity.begin());
  return velocity;
}

Bytes encodeCalibration(const std::vector<CameraModel>& cameras,
                        const std::vector<StereoCameraModel>& stereo) {
  if (cameras.empty() && stereo.empty()) return {};
  ByteWriter w;
  const bool isStereo = !stereo.empty();
  w.put<uint8_t>(isStereo ? 2 : 1);
  w.put<uint32_t>(static_cast<uint32_t>(isStereo ? stereo.size() : cameras.size()));
  const auto putModel = [&w](const std::vector<unsigned char>& bytes) {
    w.put<uint32_t>(static_cast<uint32_t>(bytes.size()));
    w.putBytes(bytes.data(), bytes.size());
  };
  if (isStereo) {
    for (const StereoCameraModel& model : stereo) putModel(model.serialize());
  } else {
    for (const CameraModel& model : cameras) putModel(model.serialize());
  }
  return w.take();
}

void decodeCalibration(const unsigned char* data, size_t size, std::vector<CameraModel>* cameras,
                       std::vector<StereoCameraModel>* stereo) {
  cameras->clear();
  stereo->clear();
  if (size == 0) return;
  ByteReader r(data, size, "camera calibration");
  const uint8_t kind = r.get<uint8_t>();
  if (kind != 1 && kind != 2) throw FormatError("stored camera calibration has unknown kind " + std::to_string(kind));
  const uint32_t count = r.get<uint32_t>();
  for (uint32_t i = 0; i < count; ++i) {
    const uint32_t modelSize = r.get<uint32_t>();
    const unsigned char* modelBytes = r.take(modelSize);
    if (kind == 2) {
      stereo->push_back(StereoCameraModel::deserialize(modelBytes, modelSize));
    } else {
      cameras->push_back(CameraModel::deserialize(modelBytes, modelSize));
    }
  }
  r.expectEnd();
}

Bytes encodeScanInfo(const SensorData::ScanInfo& info) {
  ByteWriter w(4 + 4 + 8 + 8 + 96 + 24);
  w.put<int32_t>(static_cast<int32_t>(info.format));
  w.put<int32_t>(info.maxPoints);
  w.put<double>(info.rangeMin);
  w.put<double>(info.rangeMax);
  putTransform(w, info.localTransform.isNull() ? Transform::Identity() : info.localTransform);
  w.put<double>(info.angleMin);
  w.put<double>(info.angleMax);
  w.put<double>(info.angleIncrement);
  return w.take();
}

SensorData::ScanInfo decodeScanInfo(const unsigned char* data, size_t size) {
  SensorData::ScanInfo info;
  if (size == 0) return info;
  ByteReader r(data, size, "scan info");
  const int32_t format = r.get<int32_t>();
  if (format < LaserScan::kUnknown || format > LaserScan::kXYZRGBNormal) {
    throw FormatError("stored scan info has unknown format " + std::to_string(format));
  }
  info.format = static_cast<LaserScan::Format>(format);
  info.maxPoints = r.get<int32_t>();
  info.rangeMin = r.get<double>();
  info.rangeMax = r.get<double>();
  info.localTransform = getTransform(r);
  // The beam geometry was appended to the blob: a blob without it is a scan of unknown beams.
  if (size == 4 + 4 + 8 + 8 + 96 + 24) {
    info.angleMin = r.get<double>();
    info.angleMax = r.get<double>();
    info.angleIncrement = r.get<double>();
  }
  r.expectEnd();
  return info;
}

Bytes encodeVector3f(const Eigen::Vector3f& v) {
  return encodeArray(std::vector<float>{v.x(), v.y(), v.z()});
}

Eigen::Vector3f decodeVector3f(const unsigned char* data, size_t size) {
  if (size == 0) return Eigen::Vector3f::Zero();
  const std::vector<float> values = decodeArray<float>(data, size, "view point");
  if (values.size() != 3) throw FormatError("stored view point has " + std::to_string(values.size()) + " values, not 3");
  return Eigen::Vector3f(values[0], values[1], values[2]);
}

Bytes encodeImu(const IMU& imu) {
  if (imu.empty()) return {};
  ByteWriter w(52 * 8);
  const Eigen::Quaterniond& q = imu.orientation;
  for (double v : {q.x(), q.y(), q.z(), q.w()}) w.put(v);
  putMatrix(w, imu.orientationCovariance);
  putMatrix(w, imu.angularVelocityCovariance);
  putMatrix(w, imu.linearAccelerationCovariance);
  putMatrix(w, imu.angularVelocity);
  putMatrix(w, imu.linearAcceleration);
  putTransform(w, imu.localTransform.isNull() ? Transform::Identity() : imu.localTransform);
  return w.take();
}

IMU decodeImu(const unsigned char* data, size_t size) {
  IMU imu;
  if (size == 0) return imu;
  ByteReader r(data, size, "IMU");
  const double x = r.get<double>(), y = r.get<double>(), z = r.get<double>(), qw = r.get<double>();
  imu.orientation = Eigen::Quaterniond(qw, x, y, z);
  getMatrix(r, imu.orientationCovariance);
  getMatrix(r, imu.angularVelocityCovariance);
  getMatrix(r, imu.linearAccelerationCovariance);
  getMatrix(r, imu.angularVelocity);
  getMatrix(r, imu.linearAcceleration);
  imu.localTransform = getTransform(r);
  r.expectEnd();
  return imu;
}

Bytes encodeGps(const GPS& gps) {
  if (gps.stamp == 0.0) return {};
  return encodeArray(std::vector<double>{gps.stamp, gps.longitude, gps.latitude, gps.altitude,
                                         gps.error, gps.bearing});
}

GPS decodeGps(const unsigned char* data, size_t size) {
  GPS gps;
  if (size == 0) return gps;
  const std::vector<double> v = decodeArray<double>(data, size, "GPS");
  if (v.size() != 6) throw FormatError("stored GPS has " + std::to_string(v.size()) + " values, not 6");
  gps.stamp = v[0];
  gps.longitude = v[1];
  gps.latitude = v[2];
  gps.altitude = v[3];
  gps.error = v[4];
  gps.bearing = v[5];
  return gps;
}

}  // namespace rtabmap::db::blob
