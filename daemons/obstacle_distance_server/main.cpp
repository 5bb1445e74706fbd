#include "obstacle_distance_server_node.hpp"
#include "runtime/daemon_main.hpp"

int main(int argc, char** argv) {
  return coopnav::runDaemon<coopnav::ObstacleDistanceServerNode>(
      argc, argv, "obstacle_distance_server",
      "Obstacle distance server: answers NEAREST / SIDE / RAY distance queries on the known map "
      "(request COOPNAV_DIST_REQ, reply on the request's reply_channel).");
}
