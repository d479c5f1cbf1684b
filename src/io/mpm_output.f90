!> Particle (and optional grid) output: one HDF5 file per output time plus one XDMF index.
!>
!> Each call of `write_output` writes `<dir>/particles_<NNNNNN>.h5` (NNNNNN = output index
!> 0, 1, 2, ... zero padded to 6 digits) and then rewrites `<dir>/<case name>.xdmf`, the
!> XDMF 3 time series that ParaView opens. Both are written to a `.tmp` file first and
!> renamed, so a run killed at any moment leaves an index that lists only complete files.
!> The layout of the files is described in docs/output.md.
module mpm_output
    use mpm_kinds, only: wp
    use mpm_strings, only: int_text
    use mpm_error, only: error_type, fatal_error, exit_other
    use mpm_case, only: case_type, nfields, field_displacement, field_velocity, field_stress, &
        field_strain, field_material, field_mass, field_volume, field_plastic_strain
    use mpm_particles, only: particles_type
    use mpm_grid, only: grid_type, node_position
    use mpm_hdf5, only: hdf5_location_type, text_type, hdf5_initialize, hdf5_create_file, &
        hdf5_create_group, hdf5_close, hdf5_write_dataset, hdf5_write_attribute
    use mpm_filesystem, only: directory_exists, rename_file, remove_file, file_exists
    use mpm_version, only: mpm_version_string
    implicit none
    private
    public :: output_writer_type, new_output_writer, write_output, remove_outputs

    !> One output file already written.
    type :: output_record_type
        real(wp) :: time = 0.0_wp
            !! simulated time of the output [s]
        integer :: step = 0
            !! time step number of the output
        integer :: n = 0
            !! number of particles in the file
        character(len=:), allocatable :: file
            !! file name, relative to the output folder
    end type output_record_type

    !> Writer of the output files of one run; create it with new_output_writer.
    type :: output_writer_type
        private
        character(len=:), allocatable :: dir
            !! output folder, without trailing '/'
        character(len=:), allocatable :: case_name
            !! case name, also the name of the XDMF file
        integer :: dim = 2
            !! space dimensions
        logical :: fields(nfields) = .true.
            !! fields to write (position is always written)
        logical :: grid = .false.
            !! also write the grid nodes
        type(text_type), allocatable :: materials(:)
            !! material names in case order (material index i is materials(i))
        integer :: count = 0
            !! number of output files written
        type(output_record_type), allocatable :: records(:)
            !! files written so far (1:count)
        integer :: grid_nn(3) = 1
            !! nodes per direction of the grid (it does not change during a run)
        real(wp) :: grid_origin(3) = 0.0_wp
            !! position of the first grid node, z = 0 in 2D [m]
        real(wp) :: grid_dx = 0.0_wp
            !! grid spacing [m]
    end type output_writer_type

    character(len=*), parameter :: components_2d = "xx yy zz xy"
        !! Voigt components stored in 2D
    character(len=*), parameter :: components_3d = "xx yy zz xy yz zx"
        !! Voigt components stored in 3D

contains

    !> Record the output settings of a case; no file is written yet.
    subroutine new_output_writer(writer, case, dir, error)
        type(output_writer_type), intent(out) :: writer
            !! writer to create
        type(case_type), intent(in) :: case
            !! resolved case (name, dim, output_fields, output_grid, materials)
        character(len=*), intent(in) :: dir
            !! existing output folder (created by the caller)
        type(error_type), allocatable, intent(out) :: error
            !! set when the folder does not exist or HDF5 cannot start

        integer :: i, last, m
        logical :: plastic

        if (case%dim /= 2 .and. case%dim /= 3) then
            call fatal_error(error, "output: the case has dimension "//int_text(case%dim)// &
                ", expected 2 or 3", exit_other)
            return
        end if
        if (.not. directory_exists(dir)) then
            call fatal_error(error, "the output folder '"//dir//"' does not exist", exit_other)
            return
        end if
        call hdf5_initialize(error)
        if (allocated(error)) return

        last = len_trim(dir)
        do while (last > 1)
            if (dir(last:last) /= "/") exit
            last = last - 1
        end do
        writer%dir = dir(1:last)
        if (allocated(case%name)) then
            writer%case_name = case%name
        else
            writer%case_name = "case"
        end if
        if (len(writer%case_name) == 0) writer%case_name = "case"
        writer%dim = case%dim
        writer%fields = case%output_fields
        ! the accumulated plastic shear strain exists only where a material is plastic
        plastic = .false.
        do m = 1, size(case%materials)
            plastic = plastic .or. case%materials(m)%type == "mohr_coulomb" .or. &
                case%materials(m)%type == "drucker_prager"
        end do
        writer%fields(field_plastic_strain) = writer%fields(field_plastic_strain) .and. plastic
        writer%grid = case%output_grid
        if (allocated(case%materials)) then
            allocate (writer%materials(size(case%materials)))
            do i = 1, size(case%materials)
                writer%materials(i)%text = ""
                if (allocated(case%materials(i)%name)) then
                    writer%materials(i)%text = case%materials(i)%name
                end if
            end do
        else
            allocate (writer%materials(0))
        end if
        allocate (writer%records(16))
        writer%count = 0
    end subroutine new_output_writer

    !> Write the particles (and the grid if the case asks) at one time, then the XDMF index.
    subroutine write_output(writer, step, time, particles, grid, error)
        type(output_writer_type), intent(inout) :: writer
            !! writer made by new_output_writer
        integer, intent(in) :: step
            !! time step number
        real(wp), intent(in) :: time
            !! simulated time [s]
        type(particles_type), intent(in) :: particles
            !! particles to write
        type(grid_type), intent(in) :: grid
            !! grid; written only when the case sets output_grid
        type(error_type), allocatable, intent(out) :: error
            !! set when a file cannot be written (the message names it)

        character(len=:), allocatable :: name, path
        type(output_record_type), allocatable :: grown(:)
        type(error_type), allocatable :: ignored

        if (.not. allocated(writer%dir)) then
            call fatal_error(error, "write_output called before new_output_writer", exit_other)
            return
        end if
        if (particles%dim /= writer%dim) then
            call fatal_error(error, "output: the particles have dimension "// &
                int_text(particles%dim)//" but the case has "//int_text(writer%dim), exit_other)
            return
        end if
        if (writer%grid) then
            if (.not. (allocated(grid%mass) .and. allocated(grid%velocity))) then
                call fatal_error(error, "output: grid output is on but the grid has no "// &
                    "nodal fields (new_grid not called)", exit_other)
                return
            end if
        end if

        name = particle_file_name(writer%count)
        path = writer%dir//"/"//name
        call write_hdf5_file(writer, path//".tmp", step, time, particles, grid, error)
        if (allocated(error)) then
            call remove_file(path//".tmp", ignored)
            return
        end if
        call rename_file(path//".tmp", path, error)
        if (allocated(error)) return

        if (writer%grid) then
            writer%grid_nn = grid%nn
            writer%grid_dx = grid%dx
            writer%grid_origin = 0.0_wp
            writer%grid_origin(1:writer%dim) = grid%origin(1:writer%dim)
        end if
        if (writer%count == size(writer%records)) then
            allocate (grown(2*size(writer%records)))
            grown(1:writer%count) = writer%records(1:writer%count)
            call move_alloc(grown, writer%records)
        end if
        writer%count = writer%count + 1
        writer%records(writer%count) = output_record_type(time=time, step=step, &
            n=particles%n, file=name)

        call write_xdmf(writer, error)
    end subroutine write_output

    !> One HDF5 output file: root attributes, /particles and optionally /grid.
    subroutine write_hdf5_file(writer, path, step, time, particles, grid, error)
        type(output_writer_type), intent(in) :: writer
        character(len=*), intent(in) :: path
            !! file to create
        integer, intent(in) :: step
        real(wp), intent(in) :: time
        type(particles_type), intent(in) :: particles
        type(grid_type), intent(in) :: grid
        type(error_type), allocatable, intent(out) :: error

        type(hdf5_location_type) :: file
        type(error_type), allocatable :: close_error

        call hdf5_create_file(path, file, error)
        if (allocated(error)) return
        steps: block
            call hdf5_write_attribute(file, "time", time, error)
            if (allocated(error)) exit steps
            call hdf5_write_attribute(file, "step", step, error)
            if (allocated(error)) exit steps
            call hdf5_write_attribute(file, "dimension", writer%dim, error)
            if (allocated(error)) exit steps
            call hdf5_write_attribute(file, "case_name", writer%case_name, error)
            if (allocated(error)) exit steps
            call hdf5_write_attribute(file, "mpm_geo_version", mpm_version_string, error)
            if (allocated(error)) exit steps
            call hdf5_write_attribute(file, "material_names", writer%materials, error)
            if (allocated(error)) exit steps
            call write_particles_group(writer, file, particles, error)
            if (allocated(error)) exit steps
            if (writer%grid) call write_grid_group(file, grid, error)
        end block steps
        call hdf5_close(file, close_error)
        if (.not. allocated(error) .and. allocated(close_error)) call move_alloc(close_error, error)
    end subroutine write_hdf5_file

    !> The /particles group: one row per particle, only the fields the case asks for.
    subroutine write_particles_group(writer, file, particles, error)
        type(output_writer_type), intent(in) :: writer
        type(hdf5_location_type), intent(in) :: file
        type(particles_type), intent(in) :: particles
        type(error_type), allocatable, intent(out) :: error

        type(hdf5_location_type) :: group
        type(error_type), allocatable :: close_error
        character(len=:), allocatable :: components
        real(wp), allocatable :: plastic_strain(:)

        if (writer%dim == 2) then
            components = components_2d
        else
            components = components_3d
        end if
        call hdf5_create_group(file, "particles", group, error)
        if (allocated(error)) return
        steps: block
            call write_vector(group, "position", particles%x, "m", error)
            if (allocated(error)) exit steps
            if (writer%fields(field_displacement)) then
                call write_vector(group, "displacement", particles%u, "m", error)
                if (allocated(error)) exit steps
            end if
            if (writer%fields(field_velocity)) then
                call write_vector(group, "velocity", particles%v, "m/s", error)
                if (allocated(error)) exit steps
            end if
            if (writer%fields(field_stress)) then
                call hdf5_write_dataset(group, "stress", particles%stress, error, units="Pa", &
                    components=components)
                if (allocated(error)) exit steps
            end if
            if (writer%fields(field_strain)) then
                call hdf5_write_dataset(group, "strain", particles%strain, error, units="-", &
                    components=components)
                if (allocated(error)) exit steps
            end if
            if (writer%fields(field_material)) then
                call hdf5_write_dataset(group, "material", particles%material, error, units="-")
                if (allocated(error)) exit steps
            end if
            if (writer%fields(field_mass)) then
                call hdf5_write_dataset(group, "mass", particles%mass, error, &
                    units=mass_units(writer%dim))
                if (allocated(error)) exit steps
            end if
            if (writer%fields(field_volume)) then
                call hdf5_write_dataset(group, "volume", particles%volume, error, &
                    units=volume_units(writer%dim))
                if (allocated(error)) exit steps
            end if
            if (writer%fields(field_plastic_strain) .and. particles%nstate >= 1) then
                plastic_strain = particles%state(1, :)
                call hdf5_write_dataset(group, "plastic_strain", plastic_strain, error, &
                    units="-")
                if (allocated(error)) exit steps
            end if
        end block steps
        call hdf5_close(group, close_error)
        if (.not. allocated(error) .and. allocated(close_error)) call move_alloc(close_error, error)
    end subroutine write_particles_group

    !> The /grid group: node positions, nodal mass and velocity.
    subroutine write_grid_group(file, grid, error)
        type(hdf5_location_type), intent(in) :: file
        type(grid_type), intent(in) :: grid
        type(error_type), allocatable, intent(out) :: error

        type(hdf5_location_type) :: group
        type(error_type), allocatable :: close_error
        real(wp), allocatable :: position(:, :)
        integer :: id, stat
        character(len=256) :: message

        allocate (position(3, grid%nnodes), stat=stat, errmsg=message)
        if (stat /= 0) then
            call fatal_error(error, "output: cannot allocate the grid positions: "// &
                trim(message), exit_other)
            return
        end if
        do id = 1, grid%nnodes
            position(:, id) = node_position(grid, id)
        end do
        if (grid%dim == 2) position(3, :) = 0.0_wp

        call hdf5_create_group(file, "grid", group, error)
        if (allocated(error)) return
        steps: block
            call hdf5_write_dataset(group, "position", position, error, units="m")
            if (allocated(error)) exit steps
            call hdf5_write_dataset(group, "mass", grid%mass, error, units=mass_units(grid%dim))
            if (allocated(error)) exit steps
            call write_vector(group, "velocity", grid%velocity, "m/s", error)
        end block steps
        call hdf5_close(group, close_error)
        if (.not. allocated(error) .and. allocated(close_error)) call move_alloc(close_error, error)
    end subroutine write_grid_group

    !> Write a (dim, n) vector field as an (n, 3) dataset, z = 0 in 2D.
    subroutine write_vector(group, name, values, units, error)
        type(hdf5_location_type), intent(in) :: group
        character(len=*), intent(in) :: name
        real(wp), intent(in), contiguous :: values(:, :)
            !! vectors (dim, n)
        character(len=*), intent(in) :: units
        type(error_type), allocatable, intent(out) :: error

        real(wp), allocatable :: padded(:, :)
        integer :: stat
        character(len=256) :: message

        if (size(values, 1) == 3) then
            call hdf5_write_dataset(group, name, values, error, units=units)
            return
        end if
        allocate (padded(3, size(values, 2)), stat=stat, errmsg=message)
        if (stat /= 0) then
            call fatal_error(error, "output: cannot allocate a copy of "//name//": "// &
                trim(message), exit_other)
            return
        end if
        padded = 0.0_wp
        padded(1:size(values, 1), :) = values
        call hdf5_write_dataset(group, name, padded, error, units=units)
    end subroutine write_vector

    ! ----------------------------------------------------------------------------------------
    ! XDMF
    ! ----------------------------------------------------------------------------------------

    !> Rewrite <dir>/<case>.xdmf listing every file written so far (via a .tmp and rename).
    subroutine write_xdmf(writer, error)
        type(output_writer_type), intent(in) :: writer
        type(error_type), allocatable, intent(out) :: error

        character(len=:), allocatable :: path
        character(len=256) :: message
        integer :: unit, stat, first_stat, i
        character(len=:), allocatable :: indent
        type(error_type), allocatable :: ignored

        path = writer%dir//"/"//writer%case_name//".xdmf"
        open (newunit=unit, file=path//".tmp", status="replace", action="write", &
            form="formatted", iostat=stat, iomsg=message)
        if (stat /= 0) then
            call fatal_error(error, "cannot write the XDMF file '"//path//".tmp': "// &
                trim(message), exit_other)
            return
        end if
        first_stat = 0
        indent = ""
        call put('<?xml version="1.0" ?>')
        call put('<!DOCTYPE Xdmf SYSTEM "Xdmf.dtd" []>')
        call put('<Xdmf Version="3.0" xmlns:xi="http://www.w3.org/2001/XInclude">')
        call put("  <Domain>")
        indent = ""
        if (writer%grid) then
            ! one spatial collection (particles + grid) per time: with the Xdmf3ReaderT reader
            ! ParaView names the two blocks "particles" and "grid"
            call put('    <Grid Name="particles_and_grid" GridType="Collection" '// &
                'CollectionType="Temporal">')
            do i = 1, writer%count
                call put('      <Grid Name="output_'//int_text(i - 1)// &
                    '" GridType="Collection" CollectionType="Spatial">')
                call put('        <Time Value="'//real_text(writer%records(i)%time)//'"/>')
                indent = "  "
                call put_particles(writer%records(i))
                call put_grid(writer%records(i))
                indent = ""
                call put("      </Grid>")
            end do
        else
            call put('    <Grid Name="particles" GridType="Collection" CollectionType="Temporal">')
            do i = 1, writer%count
                call put_particles(writer%records(i))
            end do
        end if
        call put("    </Grid>")
        call put("  </Domain>")
        call put("</Xdmf>")
        close (unit, iostat=stat, iomsg=message)
        if (first_stat == 0 .and. stat /= 0) first_stat = stat
        if (first_stat /= 0) then
            call fatal_error(error, "cannot write the XDMF file '"//path//".tmp': "// &
                trim(message), exit_other)
            call remove_file(path//".tmp", ignored)
            return
        end if
        call rename_file(path//".tmp", path, error)

    contains

        subroutine put(line)
            character(len=*), intent(in) :: line

            integer :: stat

            if (first_stat /= 0) return
            write (unit, "(a)", iostat=stat, iomsg=message) indent//line
            if (stat /= 0) first_stat = stat
        end subroutine put

        subroutine put_particles(record)
            type(output_record_type), intent(in) :: record

            character(len=*), parameter :: components(6) = &
                [character(len=2) :: "xx", "yy", "zz", "xy", "yz", "zx"]
            character(len=:), allocatable :: n, source
            integer :: c, nstress

            n = int_text(record%n)
            source = record%file//":/particles/"
            ! Voigt order: the first 4 components in 2D, all 6 in 3D
            nstress = merge(4, 6, writer%dim == 2)
            call put('      <Grid Name="particles" GridType="Uniform">')
            call put('        <Time Value="'//real_text(record%time)//'"/>')
            call put('        <Topology TopologyType="Polyvertex" NumberOfElements="'//n// &
                '" NodesPerElement="1"/>')
            call put('        <Geometry GeometryType="XYZ">')
            call put("          "//data_item(n//" 3", "Float", source//"position"))
            call put("        </Geometry>")
            if (writer%fields(field_displacement)) then
                call put_attribute("displacement", "Vector", n//" 3", "Float", &
                    source//"displacement")
            end if
            if (writer%fields(field_velocity)) then
                call put_attribute("velocity", "Vector", n//" 3", "Float", source//"velocity")
            end if
            if (writer%fields(field_stress)) then
                call put_attribute("stress", "Matrix", n//" "//int_text(nstress), "Float", &
                    source//"stress")
                do c = 1, nstress
                    call put_component("stress", components(c), c, nstress, n, source)
                end do
            end if
            if (writer%fields(field_strain)) then
                call put_attribute("strain", "Matrix", n//" "//int_text(nstress), "Float", &
                    source//"strain")
                do c = 1, nstress
                    call put_component("strain", components(c), c, nstress, n, source)
                end do
            end if
            if (writer%fields(field_material)) then
                call put_attribute("material", "Scalar", n, "Int", source//"material")
            end if
            if (writer%fields(field_mass)) then
                call put_attribute("mass", "Scalar", n, "Float", source//"mass")
            end if
            if (writer%fields(field_volume)) then
                call put_attribute("volume", "Scalar", n, "Float", source//"volume")
            end if
            if (writer%fields(field_plastic_strain)) then
                call put_attribute("plastic_strain", "Scalar", n, "Float", &
                    source//"plastic_strain")
            end if
            call put("      </Grid>")
        end subroutine put_particles

        !> The grid as a regular (co-rectilinear) mesh, so ParaView shows it as a surface.
        subroutine put_grid(record)
            type(output_record_type), intent(in) :: record

            character(len=:), allocatable :: nnodes, source

            nnodes = int_text(product(writer%grid_nn))
            source = record%file//":/grid/"
            call put('      <Grid Name="grid" GridType="Uniform">')
            call put('        <Time Value="'//real_text(record%time)//'"/>')
            ! XDMF lists the slowest direction first: z y x
            call put('        <Topology TopologyType="3DCoRectMesh" Dimensions="'// &
                int_text(writer%grid_nn(3))//" "//int_text(writer%grid_nn(2))//" "// &
                int_text(writer%grid_nn(1))//'"/>')
            call put('        <Geometry GeometryType="ORIGIN_DXDYDZ">')
            call put('          <DataItem Dimensions="3" NumberType="Float" Precision="8" '// &
                'Format="XML">'//real_text(writer%grid_origin(3))//" "// &
                real_text(writer%grid_origin(2))//" "//real_text(writer%grid_origin(1))// &
                "</DataItem>")
            call put('          <DataItem Dimensions="3" NumberType="Float" Precision="8" '// &
                'Format="XML">'//real_text(writer%grid_dx)//" "//real_text(writer%grid_dx)// &
                " "//real_text(writer%grid_dx)//"</DataItem>")
            call put("        </Geometry>")
            call put_attribute("mass", "Scalar", nnodes, "Float", source//"mass")
            call put_attribute("velocity", "Vector", nnodes//" 3", "Float", source//"velocity")
            call put("      </Grid>")
        end subroutine put_grid

        subroutine put_attribute(name, kind, dims, number_type, source)
            character(len=*), intent(in) :: name, kind, dims, number_type, source

            call put('        <Attribute Name="'//name//'" AttributeType="'//kind// &
                '" Center="Node">')
            call put("          "//data_item(dims, number_type, source))
            call put("        </Attribute>")
        end subroutine put_attribute

        !> Column c of an (n, nstress) dataset as a scalar attribute "<name>_<component>".
        !>
        !> The column is selected in the dataset path, "file:/dataset|start:stride:count:dims"
        !> (slowest dimension first), which the XDMF 3 library reads as an HDF5 hyperslab.
        !> ParaView 5.11 skips a DataItem with ItemType="HyperSlab" ("unrecognized array
        !> type"), so that form is not used.
        subroutine put_component(name, component, c, nstress, n, source)
            character(len=*), intent(in) :: name, component, n, source
            integer, intent(in) :: c, nstress

            call put('        <Attribute Name="'//name//"_"//component// &
                '" AttributeType="Scalar" Center="Node">')
            call put("          "//data_item(n//" 1", "Float", source//name//"|0 "// &
                int_text(c - 1)//":1 1:"//n//" 1:"//n//" "//int_text(nstress)))
            call put("        </Attribute>")
        end subroutine put_component

    end subroutine write_xdmf

    !> An XDMF DataItem pointing to an HDF5 dataset.
    pure function data_item(dims, number_type, source) result(text)
        character(len=*), intent(in) :: dims
            !! dimensions, slowest first ("n 3")
        character(len=*), intent(in) :: number_type
            !! "Float" (8 bytes) or "Int" (default integer)
        character(len=*), intent(in) :: source
            !! "file.h5:/group/dataset"
        character(len=:), allocatable :: text

        character(len=:), allocatable :: precision

        if (number_type == "Int") then
            precision = int_text(storage_size(0)/8)
        else
            precision = int_text(storage_size(0.0_wp)/8)
        end if
        text = '<DataItem Dimensions="'//dims//'" NumberType="'//number_type// &
            '" Precision="'//precision//'" Format="HDF">'//source//"</DataItem>"
    end function data_item

    pure function mass_units(dim) result(units)
        integer, intent(in) :: dim
        character(len=:), allocatable :: units

        if (dim == 2) then
            units = "kg/m"
        else
            units = "kg"
        end if
    end function mass_units

    pure function volume_units(dim) result(units)
        integer, intent(in) :: dim
        character(len=:), allocatable :: units

        if (dim == 2) then
            units = "m2"
        else
            units = "m3"
        end if
    end function volume_units

    !> A real with 17 significant digits (enough to read back the same double).
    pure function real_text(value) result(text)
        real(wp), intent(in) :: value
        character(len=:), allocatable :: text

        character(len=32) :: buffer

        write (buffer, "(es24.16e3)") value
        text = trim(adjustl(buffer))
    end function real_text

    !> Name of the particle file of output number `index` (0-based).
    pure function particle_file_name(index) result(name)
        integer, intent(in) :: index
            !! output index
        character(len=:), allocatable :: name
            !! "particles_NNNNNN.h5"

        character(len=6) :: index_text

        write (index_text, "(i6.6)") index
        name = "particles_"//index_text//".h5"
    end function particle_file_name

    !> Delete the particle files and the XDMF index an earlier run of a case left in `dir`,
    !> so an overwritten folder holds no stale outputs of a longer earlier run.
    subroutine remove_outputs(dir, case_name, error)
        character(len=*), intent(in) :: dir
            !! output folder
        character(len=*), intent(in) :: case_name
            !! case name (names the XDMF index)
        type(error_type), allocatable, intent(out) :: error
            !! set when a file cannot be deleted

        integer :: index

        call remove_file(dir//"/"//case_name//".xdmf", error)
        if (allocated(error)) return
        index = 0
        do while (file_exists(dir//"/"//particle_file_name(index)))
            call remove_file(dir//"/"//particle_file_name(index), error)
            if (allocated(error)) return
            index = index + 1
        end do
    end subroutine remove_outputs

end module mpm_output
