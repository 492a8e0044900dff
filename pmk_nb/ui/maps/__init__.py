"""The Maps screen: the maps folder, import, download, catalogues, conversion choices, access, Send."""
