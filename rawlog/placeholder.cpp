// placeholder until the TUM reader lands
