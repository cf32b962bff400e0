// point_cloud: being written.
