// expect: 12: ExternalSize -> vl_exchange: argument 2 'values' is declared with ':' but size(values, 1) is not passed
within ValidLib;
impure function ExternalSize "An unsized array whose length the C side is never told (a constant in its place)"
  input Handle handle;
  input Real values[:];
  input Boolean enabled;
  input Units unitChoice;
  output Integer status;
  output Integer counts[2];
  output Real received[3];
  output String message;
  external "C" status = vl_exchange(handle, values, 3, enabled, unitChoice, counts, received, message)
    annotation (Library = "validlib", Include = "#include \"validlib.h\"");
end ExternalSize;
