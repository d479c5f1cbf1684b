!> Build the materials of a case from their specifications.
module mpm_material_factory
    use mpm_case, only: case_type
    use mpm_material, only: material_holder_type
    use mpm_material_elastic, only: elastic_material_type, new_elastic_material
    use mpm_material_drucker_prager, only: drucker_prager_material_type, &
        new_drucker_prager_material
    use mpm_material_newtonian, only: newtonian_material_type, new_newtonian_material
    use mpm_material_mohr_coulomb, only: mohr_coulomb_material_type, new_mohr_coulomb_material
    use mpm_material_neo_hookean, only: neo_hookean_material_type, new_neo_hookean_material
    use mpm_error, only: error_type, fatal_error, exit_input
    implicit none
    private
    public :: new_materials

contains

    !> One material object per case material, in case order.
    subroutine new_materials(materials, case, error)
        type(material_holder_type), allocatable, intent(out) :: materials(:)
            !! materials of the case
        type(case_type), intent(in) :: case
            !! resolved case
        type(error_type), allocatable, intent(out) :: error
            !! set for a material type this build does not know

        integer :: i
        type(elastic_material_type) :: elastic
        type(drucker_prager_material_type) :: drucker_prager
        type(newtonian_material_type) :: newtonian
        type(mohr_coulomb_material_type) :: mohr_coulomb
        type(neo_hookean_material_type) :: neo_hookean

        allocate (materials(size(case%materials)))
        do i = 1, size(case%materials)
            associate (spec => case%materials(i))
                select case (spec%type)
                case ("linear_elastic")
                    call new_elastic_material(elastic, spec%name, spec%young, spec%poisson, &
                        spec%density)
                    allocate (materials(i)%m, source=elastic)
                case ("neo_hookean")
                    call new_neo_hookean_material(neo_hookean, spec)
                    allocate (materials(i)%m, source=neo_hookean)
                case ("mohr_coulomb")
                    call new_mohr_coulomb_material(mohr_coulomb, spec)
                    allocate (materials(i)%m, source=mohr_coulomb)
                case ("drucker_prager")
                    call new_drucker_prager_material(drucker_prager, spec)
                    allocate (materials(i)%m, source=drucker_prager)
                case ("newtonian")
                    call new_newtonian_material(newtonian, spec)
                    allocate (materials(i)%m, source=newtonian)
                case default
                    call fatal_error(error, "material '"//spec%name//"': type '"//spec%type// &
                        "' is not available in this build", exit_input)
                    return
                end select
            end associate
        end do
    end subroutine new_materials

end module mpm_material_factory
