def enclose_witness(model, falsification):
    return None
